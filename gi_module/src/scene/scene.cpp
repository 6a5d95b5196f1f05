// gi::Scene: the engine's scene packed, uploaded through the engine's command
// buffer, and bound as set 0.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <numbers>
#include <stdexcept>
#include <type_traits>

#include "gi/device.h"
#include "scene/device_meshes.h"
#include "scene/level_rebuild.h"
#include "scene/morton_order.h"
#include "scene/sky_tables.h"
#include "vulkan_error.h"

namespace gi {
namespace {

constexpr VkBufferUsageFlags kTexels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
constexpr VkBufferUsageFlags kBuildInput =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkBufferUsageFlags kAddressed =
    VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;  // read and written by bvh_refit.comp

const vk::Binding kSceneBindings[] = {
    {gpu::SCENE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},  // first: left out without ray queries
    {gpu::SCENE_BINDING_POSITIONS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_NORMALS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_UVS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_INDICES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_GEOMETRIES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_INSTANCES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_EMISSIVE_TRIANGLES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_PUNCTUAL_LIGHTS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_CONSTANTS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_NODES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_TOP_NODES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_INSTANCES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_SKY_DISTRIBUTION, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_PREVIOUS_POSITIONS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_TEXTURES, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4096, true},
};

bool rayQuery(const Scene& s) { return s.desc.traversal == Traversal::RayQuery; }
// Whether the compute traversal's BVH exists: built on the CPU only for that traversal (or both).
bool computeBvh(const Scene& s) { return !rayQuery(s) || s.desc.bothTraversals; }
bool hasDeformable(const PackedScene& p) {
  return std::find(p.meshDeformable.begin(), p.meshDeformable.end(), 1) != p.meshDeformable.end();
}
// The buffers deformable meshes' updates write on the device are reached by address.
VkBufferUsageFlags refitUsage(const Scene& s) { return hasDeformable(s.packed) ? kAddressed : 0; }

// The TLAS's instances in Morton order of their world-space centres at
// create (s.tlasOrder); updates keep that order: moving instances change
// little of it, and the sort stays off the per-frame path.
std::vector<AccelerationInstance> placedInstances(Scene& s) {
  if (s.tlasOrder.size() != s.instances.size()) {
    std::vector<glm::vec3> centres;
    for (const InstanceDesc& inst : s.instances)
      centres.push_back(glm::vec3(toMat4(inst.worldFromObject) * glm::vec4(s.packed.meshCentres[inst.mesh], 1.0f)));
    s.tlasOrder = mortonOrder(centres);
  }
  std::vector<AccelerationInstance> placed;
  for (uint32_t i : s.tlasOrder) placed.push_back({i, s.instances[i].mesh, toMat4(s.instances[i].worldFromObject)});
  return placed;
}

// A device-local buffer filled through a staging buffer copied in `cmd`.
template <typename T>
vk::Status upload(Scene& s, VkCommandBuffer cmd, const std::vector<T>& data, VkBufferUsageFlags usage,
                  vk::Buffer& out) {
  const size_t bytes = data.size() * sizeof(T), size = std::max<size_t>(bytes, 16);  // a buffer may not be empty
  GI_TRY(vk::createBuffer(s.gpu, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false, out));
  vk::Buffer& staging = s.staging.emplace_back();
  GI_TRY(vk::createBuffer(s.gpu, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, staging));
  std::memset(staging.memory.mapped, 0, size);
  if (bytes) std::memcpy(staging.memory.mapped, data.data(), bytes);
  VkBufferCopy region{0, 0, size};
  s.gpu.fn.vkCmdCopyBuffer(cmd, staging.buffer, out.buffer, 1, &region);
  return {};
}

// A host-visible buffer of `capacity` elements (at least 16 bytes), holding `data`; later writes are
// recorded into command buffers (writeInCommands).
template <typename T>
vk::Status hostBuffer(Scene& s, const std::vector<T>& data, size_t capacity, VkBufferUsageFlags usage,
                      vk::Buffer& out) {
  const size_t size = std::max<size_t>(capacity * sizeof(T), 16);
  GI_TRY(vk::createBuffer(s.gpu, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, out));
  std::memset(out.memory.mapped, 0, size);
  if (!data.empty()) std::memcpy(out.memory.mapped, data.data(), std::min(size, data.size() * sizeof(T)));
  return {};
}

// An update of a table frames in flight may read: recorded into `cmd` (between vk::beginBufferWrites and
// vk::endBufferWrites), never written by the host.
template <typename T>
void writeInCommands(const Scene& s, VkCommandBuffer cmd, const vk::Buffer& buffer, const std::vector<T>& data) {
  vk::recordBufferWrite(s.gpu, cmd, buffer, data.data(), data.size() * sizeof(T));
}

// Every array of set 0 is read as a uniform texel buffer (gpu_scene.h): on
// lavapipe a texel fetch is much cheaper, to run and to compile, than a
// storage-buffer load with a per-lane address. Structs are RGBA32UI rows
// (integers: ids and float bits pass unchanged).
// `tooLarge` names the array in the failed call's description.
vk::Status texelView(Scene& s, const vk::Buffer& buffer, VkFormat format, uint32_t texelBytes, const char* tooLarge,
                     VkBufferView& out) {
  if (buffer.size / texelBytes > s.gpu.properties.limits.maxTexelBufferElements)
    return {VK_ERROR_OUT_OF_DEVICE_MEMORY, tooLarge};
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.buffer;
  info.format = format;
  info.range = VK_WHOLE_SIZE;
  GI_VK(s.gpu.fn.vkCreateBufferView(s.gpu.device, &info, s.gpu.allocator, &out));
  return {};
}
vk::Status rowView(Scene& s, const vk::Buffer& buffer, const char* tooLarge, VkBufferView& out) {
  return texelView(s, buffer, VK_FORMAT_R32G32B32A32_UINT, 16, tooLarge, out);
}

void destroyViews(Scene& s, std::span<VkBufferView> views) {
  for (VkBufferView& v : views) {
    if (v) s.gpu.fn.vkDestroyBufferView(s.gpu.device, v, s.gpu.allocator);
    v = VK_NULL_HANDLE;
  }
}

void destroyBvhBuffers(Scene& s) {
  destroyViews(s, s.bvhViews);
  for (vk::Buffer* b : {&s.bvhNodes, &s.bvhTriangles, &s.bvhTopNodes, &s.bvhInstances}) vk::destroyBuffer(s.gpu, *b);
}

// Builds the compute BVH and stores it (bottom levels uploaded through `cmd`,
// or host-visible without one; the top level host-visible, sized for every instance).
// A scene for ray queries alone uploads none: its BVH bindings get one-element placeholders. With
// deformable meshes it keeps their levels alone on the CPU, never uploaded, for the measure that tells
// when their BLAS is built anew rather than updated (scene/level_rebuild.h).
vk::Status buildBvhBuffers(Scene& s, VkCommandBuffer cmd, std::span<const uint8_t> forceMovable) {
  if (computeBvh(s) || hasDeformable(s.packed)) {
    std::vector<BvhMesh> meshes = bvhMeshes(s.packed);
    std::vector<BvhInstance> instances = bvhInstances(s.instances, forceMovable);
    if (!computeBvh(s))  // the deformable levels alone (instances kept: per-instance facts stay aligned)
      for (size_t m = 0; m < meshes.size(); ++m)
        if (!s.packed.meshDeformable[m]) meshes[m].geometries.clear();
    try {
      s.bvh = buildSceneBvh({s.packed.positions, s.packed.indices, meshes, instances});
      s.bvhBuilds++;
    } catch (const std::bad_alloc&) {
      return {VK_ERROR_OUT_OF_HOST_MEMORY, "rtcBuildBVH (Embree's BVH build)"};
    } catch (const std::exception&) {
      return {VK_ERROR_INITIALIZATION_FAILED, "rtcBuildBVH (Embree's BVH build)"};
    }
  }
  destroyBvhBuffers(s);
  const VkBufferUsageFlags usage = kTexels | refitUsage(s);
  const SceneBvh none;
  const SceneBvh& device = computeBvh(s) ? s.bvh : none;
  if (cmd) {
    GI_TRY(upload(s, cmd, device.bottomNodes, usage, s.bvhNodes));
    GI_TRY(upload(s, cmd, device.triangles, usage, s.bvhTriangles));
  } else {
    GI_TRY(hostBuffer(s, device.bottomNodes, device.bottomNodes.size(), usage, s.bvhNodes));
    GI_TRY(hostBuffer(s, device.triangles, device.triangles.size(), usage, s.bvhTriangles));
  }
  const size_t instances = computeBvh(s) ? s.instances.size() : 0;
  GI_TRY(hostBuffer(s, device.topNodes, maxTopNodes(instances), usage, s.bvhTopNodes));
  GI_TRY(hostBuffer(s, device.topInstances, maxTopInstances(instances), usage, s.bvhInstances));
  if (hasDeformable(s.packed)) {
    if (computeBvh(s)) s.refit = refitPlan(s.bvh, s.packed.meshDeformable);
    // Room for the order of every deformable level at its capacity (a rebuild may add nodes), and each
    // level's cost as built, which its refits are weighed against.
    size_t orderCapacity = 0;
    const std::vector<BvhMesh> meshes = bvhMeshes(s.packed);
    s.builtCost.assign(meshes.size(), 0.0);
    s.costParts.assign(meshes.size(), {});
    for (size_t m = 0; m < meshes.size(); ++m) {
      if (!s.packed.meshDeformable[m] || s.bvh.meshRoot[m] == gpu::BVH_NO_CHILD) continue;
      orderCapacity += s.bvh.meshNodeCapacity[m];
      // One walk gives the cost and primes the parts the updates keep it in.
      s.builtCost[m] = meshLevelCostInParts({s.packed.positions, s.packed.indices, meshes, {}}, s.bvh, uint32_t(m),
                                            UINT32_MAX, s.costParts[m]);
    }
    vk::destroyBuffer(s.gpu, s.refitOrder);
    if (computeBvh(s)) GI_TRY(hostBuffer(s, s.refit.order, orderCapacity, kAddressed, s.refitOrder));
  }
  const vk::Buffer* buffers[] = {&s.bvhNodes, &s.bvhTriangles, &s.bvhTopNodes, &s.bvhInstances};
  for (int i = 0; i < 4; ++i)
    GI_TRY(rowView(s, *buffers[i], "vkCreateBufferView (the BVH exceeds maxTexelBufferElements)", s.bvhViews[i]));
  return {};
}

// The emission table for the instances' and vertices' current state (the buffer's words), its count and
// power in the scene's constants (both written by the caller, in its command buffer). Moves and
// deformations keep the triangles: the words fit the buffer made for them.
std::vector<uint32_t> refreshEmission(Scene& s) {
  const EmissiveTable table = emissiveTable(s.packed, s.instances);
  s.sceneConstants.emissiveTriangleCount = table.pickable();
  return emissiveTableWords(table);
}

RefitBuffers refitBuffers(const Scene& s) {
  return {deviceAddress(s.gpu, s.positions),    deviceAddress(s.gpu, s.indices),     deviceAddress(s.gpu, s.geometries),
          deviceAddress(s.gpu, s.bvhTriangles), deviceAddress(s.gpu, s.bvhNodes),    deviceAddress(s.gpu, s.refitOrder),
          deviceAddress(s.gpu, s.bvhTopNodes),  deviceAddress(s.gpu, s.bvhInstances)};
}
void writeBvhDescriptors(Scene& s) {
  vk::DescriptorWriter w(s.set[0]);
  w.uniformTexelBuffer(gpu::SCENE_BINDING_BVH_NODES, s.bvhViews[0])
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_TRIANGLES, s.bvhViews[1])
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_TOP_NODES, s.bvhViews[2])
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_INSTANCES, s.bvhViews[3]);
  w.write(s.gpu);
}

// The sky's constants, sampling tables and map (texture index = the engine's
// texture count: it is bound after them). A black sky, or a map of zeros, is
// no sky: SCENE_SPEC_HAS_SKY stays off.
vk::Status uploadSky(Scene& s, VkCommandBuffer cmd, const SkyDesc& sky, uint32_t textureCount) {
  gpu::GpuSceneConstants& c = s.sceneConstants;
  const glm::vec3 radiance(sky.radiance[0], sky.radiance[1], sky.radiance[2]);
  const bool enabled = radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f;
  std::vector<float> tables;
  if (enabled && sky.map) tables = skyDistribution(sky.map, sky.width, sky.height, sky.channels, c.skyDistributionSum);
  s.facts.hasSky = enabled && (!sky.map || c.skyDistributionSum > 0.0f);
  c.skyRadiance = s.facts.hasSky ? radiance : glm::vec3(0.0f);
  // A quarter of the light arriving from every direction (πL under a constant sky L): the irradiance of a
  // surface facing a uniform sky; a map's integral from its sampling tables' Σ luminance × sin θ.
  const double pi = std::numbers::pi;
  const double integral =
      sky.map ? double(c.skyDistributionSum) * (pi / sky.height) * (2.0 * pi / sky.width) : 4.0 * pi;
  c.skyIrradiance = float(0.25 * integral * luminance(c.skyRadiance.x, c.skyRadiance.y, c.skyRadiance.z));
  c.skyTexture = gpu::NO_TEXTURE;
  if (s.facts.hasSky && sky.map) {
    c.skyTexture = textureCount;
    c.skySize = {sky.width, sky.height};
    std::vector<float> rgba(size_t(sky.width) * sky.height * 4, 1.0f);
    for (size_t p = 0; p < size_t(sky.width) * sky.height; ++p)
      for (size_t k = 0; k < 3; ++k) rgba[4 * p + k] = sky.map[p * sky.channels + k];
    GI_TRY(vk::createImage(s.gpu, {sky.width, sky.height}, VK_FORMAT_R32G32B32A32_SFLOAT,
                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, s.skyMap));
    vk::Buffer& staging = s.staging.emplace_back();
    GI_TRY(vk::createBuffer(s.gpu, rgba.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, staging));
    std::memcpy(staging.memory.mapped, rgba.data(), rgba.size() * sizeof(float));
    vk::imageBarrier(s.gpu, cmd, s.skyMap.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {sky.width, sky.height, 1};
    s.gpu.fn.vkCmdCopyBufferToImage(cmd, staging.buffer, s.skyMap.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                                    &region);
    vk::imageBarrier(s.gpu, cmd, s.skyMap.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_READ_BIT);
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_LINEAR;
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    GI_VK(s.gpu.fn.vkCreateSampler(s.gpu.device, &info, s.gpu.allocator, &s.skySampler));
  }
  return hostBuffer(s, tables, tables.size(), kTexels, s.skyDistribution);
}

// Ray queries: a BLAS per mesh (updatable where it deforms) and the TLAS over the placed instances.
vk::Status buildAccelerationStructures(Scene& s, VkCommandBuffer cmd) {
  const PackedScene& p = s.packed;
  for (size_t m = 0; m < p.meshFirstGeometry.size(); ++m) {
    AccelerationMesh mesh;
    mesh.updatable = p.meshDeformable[m] != 0;
    for (uint32_t id = p.meshFirstGeometry[m]; id < p.meshFirstGeometry[m] + p.meshGeometryCount[m]; ++id) {
      const gpu::GpuGeometry& g = p.geometries[id];
      mesh.geometries.push_back({g.firstIndex, g.triangleCount, g.vertexOffset, p.geometryVertexCount[id],
                                 (p.materials[g.material].flags & gpu::MATERIAL_FLAG_ALPHA_MASK) == 0});
    }
    s.accelMeshes.push_back(std::move(mesh));
  }
  GI_TRY(buildSceneAcceleration(s.gpu, cmd, s.positions, s.indices, s.accelMeshes, placedInstances(s), s.accel,
                                s.staging.emplace_back()));
  return {};
}

// Set 0: the BVH, the scene's arrays as texel buffers, the textures and the sky's map.
vk::Status writeSceneDescriptors(Scene& s, const SceneContents& contents) {
  const uint32_t textureCount = uint32_t(contents.textures.size());
  const bool skyMap = s.skyMap.image != VK_NULL_HANDLE;
  GI_TRY(vk::createDescriptorSets(s.gpu, sceneBindings(rayQuery(s)), 1, s.set, VK_NULL_HANDLE,
                                  textureCount + (skyMap ? 1u : 0u)));
  writeBvhDescriptors(s);
  vk::DescriptorWriter w(s.set[0]);
  if (rayQuery(s)) w.accelerationStructure(gpu::SCENE_BINDING_TLAS, &s.accel.tlas.handle);
  const struct {
    uint32_t binding;
    const vk::Buffer* buffer;
    VkFormat format;
    uint32_t texelBytes;
    const char* tooLarge;
  } arrays[] = {
      {gpu::SCENE_BINDING_POSITIONS, &s.positions, VK_FORMAT_R32_SFLOAT, 4,
       "vkCreateBufferView (the positions exceed maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_PREVIOUS_POSITIONS, s.previousPositions.buffer ? &s.previousPositions : &s.positions,
       VK_FORMAT_R32_SFLOAT, 4, "vkCreateBufferView (the positions exceed maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_NORMALS, &s.normals, VK_FORMAT_R32_SFLOAT, 4,
       "vkCreateBufferView (the normals exceed maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_UVS, &s.uvs, VK_FORMAT_R32G32_SFLOAT, 8,
       "vkCreateBufferView (the texture coordinates exceed maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_INDICES, &s.indices, VK_FORMAT_R32_UINT, 4,
       "vkCreateBufferView (the indices exceed maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_GEOMETRIES, &s.geometries, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the geometry table exceeds maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_INSTANCES, &s.instanceTable, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the instance table exceeds maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_MATERIALS, &s.materials, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the material table exceeds maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_EMISSIVE_TRIANGLES, &s.emissiveTriangles, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the emission table exceeds maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_PUNCTUAL_LIGHTS, &s.punctualLights, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the light table exceeds maxTexelBufferElements)"},
      {gpu::SCENE_BINDING_SKY_DISTRIBUTION, &s.skyDistribution, VK_FORMAT_R32_SFLOAT, 4,
       "vkCreateBufferView (the sky's tables exceed maxTexelBufferElements)"},
      // A texel buffer, not a uniform buffer: lavapipe compiles a variant of every program for the values of
      // the uniforms its branches and loops test (the light counts), so a uniform buffer would give each
      // scene programs of its own, compiled anew at their first dispatch.
      {gpu::SCENE_BINDING_CONSTANTS, &s.constants, VK_FORMAT_R32G32B32A32_UINT, 16,
       "vkCreateBufferView (the scene's constants)"}};
  static_assert(std::size(arrays) == std::extent_v<decltype(Scene::arrayViews)>);
  for (size_t i = 0; i < std::size(arrays); ++i) {
    GI_TRY(
        texelView(s, *arrays[i].buffer, arrays[i].format, arrays[i].texelBytes, arrays[i].tooLarge, s.arrayViews[i]));
    w.uniformTexelBuffer(arrays[i].binding, s.arrayViews[i]);
  }
  for (uint32_t t = 0; t < textureCount; ++t)
    w.sampledImage(gpu::SCENE_BINDING_TEXTURES, contents.textures[t].view, contents.textures[t].sampler, t);
  if (skyMap) w.sampledImage(gpu::SCENE_BINDING_TEXTURES, s.skyMap.view, s.skySampler, textureCount);
  w.write(s.gpu);
  return {};
}

// What the module needs to know about the scene (SceneDesc), from what was built.
void setSceneFacts(Scene& s, const SceneContents& contents) {
  const PackedScene& p = s.packed;
  const gpu::GpuSceneConstants& c = s.sceneConstants;
  s.facts.layout = s.set.layout;
  s.facts.set = s.set[0];
  s.facts.hasEmissiveTriangles = c.emissiveTriangleCount > 0;
  s.facts.emissiveTriangles = c.emissiveTriangleCount;
  s.facts.hasPunctualLights = c.punctualLightCount > 0;
  setLightFacts(c, s.facts);
  s.facts.hasAlphaMask = p.hasAlphaMask;
  s.facts.hasGlossyMaterials = p.hasGlossyMaterials;
  s.facts.extent = c.sceneExtent;
  s.facts.typicalRadiance = typicalRadiance(p, contents.lights, contents.sky, c.sceneExtent);
  s.facts.traversal = s.desc.traversal;
  s.facts.hasComputeBvh = computeBvh(s);
}

vk::Status buildScene(Scene& s, VkCommandBuffer cmd, const SceneContents& contents) {
  const PackedScene& p = s.packed;
  const VkBufferUsageFlags geometryUsage = kTexels | (rayQuery(s) ? kBuildInput : 0) | refitUsage(s);
  GI_TRY(upload(s, cmd, p.positions, geometryUsage | (hasDeformable(p) ? VK_BUFFER_USAGE_TRANSFER_SRC_BIT : 0),
                s.positions));
  if (hasDeformable(p)) GI_TRY(upload(s, cmd, p.positions, kTexels, s.previousPositions));
  GI_TRY(upload(s, cmd, p.normals, kTexels | refitUsage(s), s.normals));
  GI_TRY(upload(s, cmd, p.uvs, kTexels, s.uvs));
  GI_TRY(upload(s, cmd, p.indices, geometryUsage, s.indices));
  GI_TRY(upload(s, cmd, p.geometries, kTexels | refitUsage(s), s.geometries));
  if (hasDeformable(p) && computeBvh(s)) GI_TRY(createRefitProgram(s.gpu, s.refitProgram));  // its refits
  if (hasDeformable(p)) GI_TRY(createPositionsReadback(s));                   // the device streams' measure
  if (hasDeformable(p)) GI_TRY(createGatherProgram(s.gpu, s.gatherProgram));  // device streams
  GI_TRY(upload(s, cmd, p.materials, kTexels, s.materials));

  GI_TRY(hostBuffer(s, gpuInstances(p, s.instances, {}), s.instances.size(), kTexels, s.instanceTable));
  const EmissiveTable emissive = emissiveTable(p, s.instances);
  GI_TRY(hostBuffer(s, emissiveTableWords(emissive), emissiveTableCapacityWords(emissive.triangles.size()), kTexels,
                    s.emissiveTriangles));
  gpu::GpuSceneConstants& c = s.sceneConstants;
  glm::vec3 lo, hi;
  worldBounds(p, s.instances, lo, hi);
  const bool empty = lo.x > hi.x;
  c.emissiveTriangleCount = emissive.pickable();
  // An empty scene (nothing streamed in yet) still needs a scale for depth guidance: 1 m.
  c.sceneExtent = empty ? 1.0f : std::max(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}), 1e-6f);
  c.boundsMin = empty ? glm::vec3(0.0f) : lo;
  c.boundsMax = empty ? glm::vec3(0.0f) : hi;
  const LightTable lights = lightTable(contents.lights, c.sceneExtent, s.desc.lightTreeCut);
  GI_TRY(
      hostBuffer(s, lightTableWords(lights), lightTableCapacityWords(lights.lights.size()), kTexels, s.punctualLights));
  c.punctualLightCount = uint32_t(lights.lights.size());
  c.directionalLightCount = lights.directionalCount;
  c.lightCutSize = uint32_t(lights.cut.size());
  c.lightSampler = uint32_t(s.desc.lightSampler);
  const uint32_t textureCount = uint32_t(contents.textures.size());
  GI_TRY(uploadSky(s, cmd, contents.sky, textureCount));
  c.textureCount = textureCount + (s.skyMap.image != VK_NULL_HANDLE ? 1u : 0u);
  GI_TRY(hostBuffer(s, std::vector<gpu::GpuSceneConstants>{c}, 1, kTexels, s.constants));

  // Everything copied so far is read by the builds below and by shaders.
  vk::memoryBarrier(s.gpu, cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_UNIFORM_READ_BIT |
                        (rayQuery(s) ? VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR : 0));
  GI_TRY(buildBvhBuffers(s, cmd, {}));
  if (rayQuery(s)) GI_TRY(buildAccelerationStructures(s, cmd));
  // The BVH's bottom levels were copied after the first barrier.
  vk::memoryBarrier(s.gpu, cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_READ_BIT);

  GI_TRY(writeSceneDescriptors(s, contents));
  setSceneFacts(s, contents);
  return {};
}

void freeStaging(Scene& s) {
  for (vk::Buffer& b : s.staging) vk::destroyBuffer(s.gpu, b);
  s.staging.clear();
}

void destroySceneResources(Scene& s) {
  s.rebuildJob.reset();  // waits for a level rebuild still running: it reads the scene's indices
  destroyPositionsReadback(s);
  freeStaging(s);
  destroyDeviceMeshReadback(s.gpu, s.readback);
  destroyBvhBuffers(s);
  destroyViews(s, s.arrayViews);
  destroySceneAcceleration(s.gpu, s.accel);
  vk::destroyDescriptorSets(s.gpu, s.set);
  vk::destroyImage(s.gpu, s.skyMap);
  if (s.skySampler) s.gpu.fn.vkDestroySampler(s.gpu.device, s.skySampler, s.gpu.allocator);
  s.skySampler = VK_NULL_HANDLE;
  for (vk::Buffer* b :
       {&s.positions, &s.previousPositions, &s.normals, &s.uvs, &s.indices, &s.geometries, &s.materials,
        &s.instanceTable, &s.emissiveTriangles, &s.punctualLights, &s.constants, &s.skyDistribution, &s.refitOrder})
    vk::destroyBuffer(s.gpu, *b);
  vk::destroyComputeProgram(s.gpu, s.refitProgram);
  vk::destroyComputeProgram(s.gpu, s.gatherProgram);
  vk::closeDevice(s.gpu);
}

Error sceneError(std::string message) { return {ErrorCode::OutOfRange, std::move(message)}; }

// Checks and packs CPU-array contents and keeps what updates need; "" when good.
std::string prepare(Scene& s, const SceneContents& contents) {
  if (std::string e = packScene(contents, s.packed); !e.empty()) return e;
  if (std::string e = checkInstances(s.packed, contents.instances, "contents.instances"); !e.empty()) return e;
  if (std::string e = checkLights(contents.lights, "contents.lights"); !e.empty()) return e;
  s.instances.assign(contents.instances.begin(), contents.instances.end());
  for (InstanceDesc& inst : s.instances) {
    inst.movable |= s.packed.meshDeformable[inst.mesh] != 0;  // its bottom level is its mesh's own, refit in place
    s.previousTransforms.push_back(toMat4(inst.worldFromObject));
  }
  s.lightCount = contents.lights.size();
  return {};
}

}  // namespace

std::span<const vk::Binding> sceneBindings(bool rayQuery) {
  return rayQuery ? std::span<const vk::Binding>(kSceneBindings)
                  : std::span<const vk::Binding>(kSceneBindings).subspan(1);
}

Error createScene(const SceneCreateDesc& desc, const SceneContents& contents, VkCommandBuffer cmd, Scene*& out) {
  out = nullptr;
  if (desc.structSize != sizeof(SceneCreateDesc))
    return {ErrorCode::VersionMismatch, "gi::createScene: desc.structSize = " + std::to_string(desc.structSize) +
                                            ", this library's SceneCreateDesc is " +
                                            std::to_string(sizeof(SceneCreateDesc))};
  if (!desc.instance || !desc.physicalDevice || !desc.device || !desc.getInstanceProcAddr || !cmd)
    return {ErrorCode::MissingHandle,
            "gi::createScene: instance, physicalDevice, device, getInstanceProcAddr and cmd "
            "are required"};
  if (desc.traversal != Traversal::RayQuery && desc.traversal != Traversal::Compute)
    return sceneError("gi::createScene: desc.traversal = " + std::to_string(uint32_t(desc.traversal)) +
                      " is not Traversal::RayQuery or Traversal::Compute");
  if (desc.lightTreeCut < 1 || desc.lightTreeCut > 64)
    return sceneError("gi::createScene: desc.lightTreeCut = " + std::to_string(desc.lightTreeCut) +
                      " is outside [1, 64]");
  if (desc.lightSampler > gpu::LIGHT_SAMPLER_TREE)
    return sceneError("gi::createScene: desc.lightSampler = " + std::to_string(desc.lightSampler) +
                      " is not gpu::LIGHT_SAMPLER_ALL, LIGHT_SAMPLER_POWER or LIGHT_SAMPLER_TREE");
  if (!(desc.rebuildCostRatio >= 0.0f) || !std::isfinite(desc.rebuildCostRatio))
    return sceneError("gi::createScene: desc.rebuildCostRatio = " + std::to_string(desc.rebuildCostRatio) +
                      " is not a finite ratio ≥ 0 (0: never rebuild)");
  auto s = std::make_unique<Scene>();
  s->desc = desc;
  bool deviceMeshes = false;
  for (size_t m = 0; m < contents.meshes.size(); ++m)
    if (isDeviceMesh(contents.meshes[m])) {
      deviceMeshes = true;
      if (std::string e = checkDeviceMesh(contents.meshes[m], "contents.meshes[" + std::to_string(m) + "]"); !e.empty())
        return sceneError("gi::createScene: " + e);
    }
  if (!deviceMeshes)
    if (std::string e = prepare(*s, contents); !e.empty()) return sceneError("gi::createScene: " + e);
  if (desc.traversal == Traversal::RayQuery && contents.instances.size() > (1u << 24))
    return sceneError("gi::createScene: " + std::to_string(contents.instances.size()) +
                      " instances; ray queries index at most 2^24 (a TLAS instance's custom index)");

  if (Error e = checkDeviceMemory(desc.deviceMemory, "gi::createScene: desc.deviceMemory")) return e;
  s->gpu.allocator = desc.allocationCallbacks;
  s->gpu.memory.budget = desc.memoryBudgetBytes;
  s->gpu.memory.engine = desc.deviceMemory;
  // Acceleration-structure inputs and the device meshes' read-back are used through device addresses.
  const bool deformable =
      std::any_of(contents.meshes.begin(), contents.meshes.end(), [](const MeshDesc& m) { return m.deformable; });
  s->gpu.deviceAddressMemory = desc.traversal == Traversal::RayQuery || deviceMeshes || deformable;
  if (vk::Status st = vk::openDevice(desc.getInstanceProcAddr, desc.instance, desc.physicalDevice, desc.device, s->gpu))
    return {ErrorCode::MissingHandle, std::string("gi::createScene: desc.getInstanceProcAddr returned no ") + st.call,
            st.result};
  if (rayQuery(*s) && !s->gpu.fn.vkCmdBuildAccelerationStructuresKHR) {
    vk::closeDevice(s->gpu);
    return {ErrorCode::MissingFeature,
            "gi::createScene: Traversal::RayQuery needs VK_KHR_acceleration_structure, "
            "which the device was created without"};
  }
  if ((deviceMeshes || deformable) && !s->gpu.fn.vkGetBufferDeviceAddress) {
    vk::closeDevice(s->gpu);
    return {ErrorCode::MissingFeature,
            "gi::createScene: device and deformable meshes need bufferDeviceAddress (Vulkan 1.2)"};
  }
  vk::Status st;
  if (deviceMeshes) {
    holdContents(contents, s->held);
    s->awaitingGeometry = true;
    st = recordDeviceMeshReadback(s->gpu, cmd, s->held, s->readback);
  } else {
    st = buildScene(*s, cmd, contents);
  }
  if (st) {
    Error e = vulkanError("gi::createScene", st);
    destroySceneResources(*s);
    return e;
  }
  out = s.release();
  return {};
}

Error finishSceneUpload(Scene* s, VkCommandBuffer cmd) {
  if (!s) return {};
  freeStaging(*s);
  if (!s->awaitingGeometry) return {};
  if (!cmd)
    return {ErrorCode::MissingHandle,
            "gi::finishSceneUpload: cmd is required (the scene's device meshes are built now)"};
  s->awaitingGeometry = false;  // one attempt: a failed build leaves the scene unbuilt, for destroyScene
  takeDeviceMeshes(s->readback, s->held);
  destroyDeviceMeshReadback(s->gpu, s->readback);
  const SceneContents contents = heldView(s->held);
  if (std::string e = prepare(*s, contents); !e.empty()) return sceneError("gi::finishSceneUpload: " + e);
  if (vk::Status st = buildScene(*s, cmd, contents)) {
    s->facts = SceneDesc{};
    return vulkanError("gi::finishSceneUpload", st);
  }
  s->held = HeldContents{};
  return {};
}

bool sceneBuilt(const Scene* s) { return s && s->facts.set != VK_NULL_HANDLE; }

void destroyScene(Scene* s) {
  if (!s) return;
  destroySceneResources(*s);
  delete s;
}

SceneDesc sceneDesc(const Scene* s) { return s->facts; }

Error updateInstances(Scene* s, VkCommandBuffer cmd, std::span<const InstanceDesc> instances) {
  if (!sceneBuilt(s))
    return {ErrorCode::MissingHandle, "gi::updateInstances: the scene is not built (finishSceneUpload)"};
  if (instances.size() != s->instances.size())
    return sceneError("gi::updateInstances: " + std::to_string(instances.size()) + " instances given, the scene has " +
                      std::to_string(s->instances.size()));
  if (std::string e = checkInstances(s->packed, instances, "instances"); !e.empty())
    return sceneError("gi::updateInstances: " + e);
  for (size_t i = 0; i < instances.size(); ++i)
    if (instances[i].mesh != s->instances[i].mesh)
      return sceneError("gi::updateInstances: instances[" + std::to_string(i) + "].mesh changed from " +
                        std::to_string(s->instances[i].mesh) + " to " + std::to_string(instances[i].mesh));
  if (!cmd)
    return {ErrorCode::MissingHandle, "gi::updateInstances: cmd is VK_NULL_HANDLE (the tables are written in it)"};
  // Last update's transforms become the previous ones (motion vectors).
  for (size_t i = 0; i < instances.size(); ++i) s->previousTransforms[i] = toMat4(s->instances[i].worldFromObject);
  std::vector<uint8_t> moved(instances.size(), 0);
  bool mergedMoved = false;
  for (size_t i = 0; computeBvh(*s) && i < instances.size() && i < s->bvh.merged.size(); ++i) {
    moved[i] = s->bvh.merged[i] && toMat4(instances[i].worldFromObject) != s->bvh.mergedTransforms[i];
    mergedMoved |= moved[i] != 0;
  }
  bool emitterMoved = false;  // the emission table (its areas, cdf and tree) follows only emitters' moves
  for (size_t i = 0; i < instances.size(); ++i) {
    const bool movable = s->instances[i].movable || moved[i];
    emitterMoved |=
        toMat4(instances[i].worldFromObject) != s->previousTransforms[i] && meshEmits(s->packed, instances[i].mesh);
    s->instances[i] = instances[i];
    s->instances[i].movable = movable;
  }
  const std::vector<uint32_t> emissive = emitterMoved ? refreshEmission(*s) : std::vector<uint32_t>{};
  if (mergedMoved) {  // merged as static: taken out once, its level rebuilt (new buffers, set 0 rewritten)
    if (vk::Status st = buildBvhBuffers(*s, VK_NULL_HANDLE, moved)) return vulkanError("gi::updateInstances", st);
    writeBvhDescriptors(*s);
  } else if (computeBvh(*s)) {
    try {
      rebuildTopLevel(bvhInstances(s->instances, {}), s->bvh);
    } catch (const std::exception& e) {
      return {ErrorCode::VulkanCall, std::string("gi::updateInstances: the BVH's top level: ") + e.what(),
              VK_ERROR_INITIALIZATION_FAILED};
    }
  }
  // The tables travel in `cmd`: frames in flight keep reading the previous ones.
  vk::beginBufferWrites(s->gpu, cmd);
  writeInCommands(*s, cmd, s->instanceTable, gpuInstances(s->packed, s->instances, s->previousTransforms));
  if (emitterMoved) writeInCommands(*s, cmd, s->emissiveTriangles, emissive);
  writeInCommands(*s, cmd, s->constants, std::vector<gpu::GpuSceneConstants>{s->sceneConstants});
  if (!mergedMoved && computeBvh(*s)) {
    writeInCommands(*s, cmd, s->bvhTopNodes, s->bvh.topNodes);
    writeInCommands(*s, cmd, s->bvhInstances, s->bvh.topInstances);
  }
  if (rayQuery(*s)) writeTlasInstances(s->gpu, cmd, placedInstances(*s), s->accel);
  vk::endBufferWrites(s->gpu, cmd);
  // The CPU's boxes of deformed meshes are their last CPU-known pose's: the device refits the top level.
  if (hasDeformable(s->packed) && computeBvh(*s))
    recordTopRefit(s->gpu, cmd, s->refitProgram, refitBuffers(*s), uint32_t(s->bvh.topNodes.size()));
  if (rayQuery(*s)) recordTlasRebuild(s->gpu, cmd, s->accel);
  return {};
}

// Deformable mesh `mesh`'s current positions copied to its previous ones (set 0's, which the G-buffer's
// motion vectors read), after every earlier command's reads and writes of the vertices, before every later
// transfer or compute write.
void recordPreviousPositions(Scene& s, VkCommandBuffer cmd, uint32_t mesh) {
  const PackedScene& p = s.packed;
  std::vector<VkBufferCopy> previous;
  for (uint32_t id = p.meshFirstGeometry[mesh]; id < p.meshFirstGeometry[mesh] + p.meshGeometryCount[mesh]; ++id) {
    const VkDeviceSize at = VkDeviceSize(p.geometries[id].vertexOffset) * 12;
    previous.push_back({at, at, VkDeviceSize(p.geometryVertexCount[id]) * 12});
  }
  s.gpu.fn.vkCmdCopyBuffer(cmd, s.positions.buffer, s.previousPositions.buffer, uint32_t(previous.size()),
                           previous.data());
  vk::memoryBarrier(
      s.gpu, cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT,
      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
      VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_MEMORY_READ_BIT);
}

// The checks both vertex calls make: a built scene, a command buffer, a deformable mesh.
Error checkDeformableMesh(const Scene* s, VkCommandBuffer cmd, uint32_t mesh, const char* caller) {
  if (!sceneBuilt(s))
    return {ErrorCode::MissingHandle, std::string(caller) + ": the scene is not built (finishSceneUpload)"};
  if (!cmd)
    return {ErrorCode::MissingHandle, std::string(caller) + ": cmd is VK_NULL_HANDLE (the vertices are written in it)"};
  const PackedScene& p = s->packed;
  if (mesh >= p.meshDeformable.size())
    return sceneError(std::string(caller) + ": mesh " + std::to_string(mesh) + " is not below the scene's " +
                      std::to_string(p.meshDeformable.size()) + " meshes");
  if (!p.meshDeformable[mesh])
    return sceneError(std::string(caller) + ": mesh " + std::to_string(mesh) +
                      " was not created deformable (MeshDesc::deformable)");
  return {};
}

Error updateMeshVertices(Scene* s, VkCommandBuffer cmd, uint32_t mesh, const MeshVertices& v) {
  if (Error e = checkDeformableMesh(s, cmd, mesh, "gi::updateMeshVertices")) return e;
  PackedScene& p = s->packed;
  const uint32_t firstGeometry = p.meshFirstGeometry[mesh], geometryEnd = firstGeometry + p.meshGeometryCount[mesh];
  uint32_t vertexCount = 0;  // the mesh's arrays reach this far
  for (uint32_t id = firstGeometry; id < geometryEnd; ++id)
    vertexCount = std::max(vertexCount, p.geometryFirstVertex[id] + p.geometryVertexCount[id]);
  const bool emissive = meshEmits(p, mesh);
  const bool device = v.devicePositions.address || v.deviceNormals.address;
  if (device) {
    if (v.positions || v.normals)
      return sceneError("gi::updateMeshVertices: vertices: device streams and CPU arrays both given");
    if (std::string e = checkVertexStreams(v.devicePositions, v.deviceNormals, vertexCount, "vertices"); !e.empty())
      return sceneError("gi::updateMeshVertices: " + e);
  } else {
    if (!v.positions || !v.normals)
      return sceneError(
          "gi::updateMeshVertices: vertices.positions and vertices.normals are required (or device streams)");
    for (uint32_t i = 0; i < vertexCount; ++i) {
      const float* pos = element(v.positions, v.positionStride, 12, i);
      if (!std::isfinite(pos[0]) || !std::isfinite(pos[1]) || !std::isfinite(pos[2]))
        return sceneError("gi::updateMeshVertices: vertices.positions[" + std::to_string(i) + "] is not finite");
    }
  }
  // Every earlier command's reads of the vertices and the BVH (frames in flight) before the writes, and the
  // last update's writes of the positions before the copy reads them.
  vk::memoryBarrier(
      s->gpu, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
      VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
      VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
      VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  // This pose's positions become the previous ones (the G-buffer's motion vectors), then the new ones follow.
  recordPreviousPositions(*s, cmd, mesh);
  const VkDeviceAddress positions = deviceAddress(s->gpu, s->positions), normals = deviceAddress(s->gpu, s->normals);
  for (uint32_t id = firstGeometry; id < geometryEnd; ++id) {
    const uint32_t first = p.geometryFirstVertex[id], count = p.geometryVertexCount[id],
                   at = p.geometries[id].vertexOffset;
    if (device) {
      recordVertexGather(s->gpu, cmd, s->gatherProgram, v.devicePositions, false, first, count, positions + 12ull * at);
      recordVertexGather(s->gpu, cmd, s->gatherProgram, v.deviceNormals, true, first, count, normals + 12ull * at);
      continue;
    }
    for (uint32_t i = 0; i < count; ++i) {
      std::memcpy(&p.positions[at + i], element(v.positions, v.positionStride, 12, first + i), 12);
      std::memcpy(&p.normals[at + i], element(v.normals, v.normalStride, 12, first + i), 12);
    }
    vk::recordBufferWrite(s->gpu, cmd, s->positions, &p.positions[at], size_t(count) * 12, VkDeviceSize(at) * 12);
    vk::recordBufferWrite(s->gpu, cmd, s->normals, &p.normals[at], size_t(count) * 12, VkDeviceSize(at) * 12);
  }
  if (!device && emissive) {  // the emission table follows the new areas
    writeInCommands(*s, cmd, s->emissiveTriangles, refreshEmission(*s));
    writeInCommands(*s, cmd, s->constants, std::vector<gpu::GpuSceneConstants>{s->sceneConstants});
  }
  const LevelUpdate level = device ? followDeviceLevel(*s, cmd, mesh) : rebuildDegradedLevel(*s, cmd, mesh);
  // The vertices before the refit, the BLAS update and every later reader.
  vk::memoryBarrier(s->gpu, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  if (computeBvh(*s)) {
    const RefitBuffers buffers = refitBuffers(*s);
    if (!level.nodesBuilt) recordMeshRefit(s->gpu, cmd, s->refitProgram, buffers, s->refit, mesh);
    recordTopRefit(s->gpu, cmd, s->refitProgram, buffers, uint32_t(s->bvh.topNodes.size()));
  }
  if (rayQuery(*s)) {
    recordBlasUpdate(s->gpu, cmd, s->positions, s->indices, s->accelMeshes[mesh], s->accel, mesh, level.blasBuild);
    recordTlasRebuild(s->gpu, cmd, s->accel);
  }
  if (device) recordPositionsReadback(*s, cmd, mesh);  // for a later update's measure
  return {};
}

Error holdMeshVertices(Scene* s, VkCommandBuffer cmd, uint32_t mesh) {
  if (Error e = checkDeformableMesh(s, cmd, mesh, "gi::holdMeshVertices")) return e;
  // Every earlier command's reads and writes of the positions (frames in flight, the last update) first.
  vk::memoryBarrier(s->gpu, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
  recordPreviousPositions(*s, cmd, mesh);
  return {};
}

Error updateLights(Scene* s, VkCommandBuffer cmd, std::span<const LightDesc> lights) {
  if (!sceneBuilt(s)) return {ErrorCode::MissingHandle, "gi::updateLights: the scene is not built (finishSceneUpload)"};
  if (!cmd) return {ErrorCode::MissingHandle, "gi::updateLights: cmd is VK_NULL_HANDLE (the tables are written in it)"};
  if (lights.size() != s->lightCount)
    return sceneError("gi::updateLights: " + std::to_string(lights.size()) + " lights given, the scene has " +
                      std::to_string(s->lightCount));
  if (std::string e = checkLights(lights, "lights"); !e.empty()) return sceneError("gi::updateLights: " + e);
  // Updates may turn lights into directional ones and back: the count and the tree follow.
  const LightTable table = lightTable(lights, s->sceneConstants.sceneExtent, s->desc.lightTreeCut);
  vk::beginBufferWrites(s->gpu, cmd);
  writeInCommands(*s, cmd, s->punctualLights, lightTableWords(table));
  if (table.directionalCount != s->sceneConstants.directionalLightCount ||
      table.cut.size() != s->sceneConstants.lightCutSize) {
    s->sceneConstants.directionalLightCount = table.directionalCount;
    s->sceneConstants.lightCutSize = uint32_t(table.cut.size());
    writeInCommands(*s, cmd, s->constants, std::vector<gpu::GpuSceneConstants>{s->sceneConstants});
    setLightFacts(s->sceneConstants, s->facts);  // gi::sceneDesc's from now on
  }
  vk::endBufferWrites(s->gpu, cmd);
  return {};
}

SceneInfo sceneInfo(const Scene* s) {
  SceneInfo info;
  for (const InstanceDesc& inst : s->instances)
    for (uint32_t id = s->packed.meshFirstGeometry[inst.mesh];
         id < s->packed.meshFirstGeometry[inst.mesh] + s->packed.meshGeometryCount[inst.mesh]; ++id)
      info.triangles += s->packed.geometries[id].triangleCount;
  info.emissiveTriangles = s->sceneConstants.emissiveTriangleCount;
  info.levelRebuildRunning = s->rebuildJob != nullptr;
  info.bvhBottomBuildMs = s->bvh.bottomBuildMs;
  info.bvhTopBuildMs = s->bvh.topBuildMs;
  info.memoryBytes = s->gpu.memory.held;
  info.refitCostRatio = s->refitCostRatio;
  info.levelRebuilds = s->levelRebuilds;
  for (int k = 0; k < 3; ++k) {
    info.boundsMin[k] = s->sceneConstants.boundsMin[k];
    info.boundsMax[k] = s->sceneConstants.boundsMax[k];
  }
  return info;
}

}  // namespace gi
