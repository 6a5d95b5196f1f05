#include "scene_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace engine {
namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr VkBufferUsageFlags kBuildInput = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                           VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                                           VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

const Binding kSceneBindings[] = {
    {gpu::SCENE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},  // first: left out without ray queries
    {gpu::SCENE_BINDING_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_NORMALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_UVS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_GEOMETRIES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_INSTANCES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_EMISSIVE_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_PUNCTUAL_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_CONSTANTS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
    {gpu::SCENE_BINDING_BVH_NODES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_TOP_NODES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_BVH_INSTANCES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
    {gpu::SCENE_BINDING_SKY_DISTRIBUTION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::SCENE_BINDING_TEXTURES, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4096, true},
};


template <typename T>
Buffer upload(const Context& ctx, const std::vector<T>& data, VkBufferUsageFlags usage) {
  return createBufferWithData(ctx, data.data(), data.size() * sizeof(T), usage);
}

std::vector<gpu::GpuInstance> gpuInstances(const Scene& scene, const std::vector<glm::mat4>& previous) {
  std::vector<gpu::GpuInstance> out;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    gpu::GpuInstance g{};
    g.worldFromObject = inst.worldFromObject;
    g.normalWorldFromObject = glm::mat4(glm::transpose(glm::inverse(glm::mat3(inst.worldFromObject))));
    g.previousWorldFromObject = i < previous.size() ? previous[i] : inst.worldFromObject;
    g.firstGeometry = scene.meshes[inst.mesh].firstPrimitive;
    g.geometryCount = scene.meshes[inst.mesh].primitiveCount;
    out.push_back(g);
  }
  return out;
}

// The NEE table: one entry per emissive (instance, triangle), picked in
// proportion to world area × luminance(emission).
std::vector<gpu::GpuEmissiveTriangle> emissiveTable(const Scene& scene, float& totalPower) {
  std::vector<gpu::GpuEmissiveTriangle> table;
  std::vector<double> weights;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
      const Primitive& prim = scene.primitives[p];
      const Material& mat = scene.materials[prim.material];
      if (!mat.isEmissive()) continue;
      for (uint32_t t = 0; t < prim.indexCount / 3; ++t) {
        glm::vec3 v[3];
        for (int k = 0; k < 3; ++k)
          v[k] = glm::vec3(inst.worldFromObject *
                           glm::vec4(scene.positions[prim.vertexOffset + scene.indices[prim.firstIndex + 3 * t + k]], 1.0f));
        double area = 0.5 * double(glm::length(glm::cross(v[1] - v[0], v[2] - v[0])));
        double w = area * double(luminance(mat.emission));
        if (!(w > 0.0) || !std::isfinite(w)) continue;  // zero-area triangles can never be hit nor sampled
        table.push_back({i, p, t, 0.0f});
        weights.push_back(w);
      }
    }
  }
  double total = 0.0;
  for (double w : weights) total += w;
  double running = 0.0;
  for (size_t k = 0; k < table.size(); ++k) {
    running += weights[k];
    table[k].cdf = float(running / total);
  }
  if (!table.empty()) table.back().cdf = 1.0f;
  totalPower = float(total);
  return table;
}

std::vector<gpu::GpuPunctualLight> punctualLights(const Scene& scene) {
  std::vector<gpu::GpuPunctualLight> out;
  for (const PunctualLight& l : scene.lights) {
    gpu::GpuPunctualLight g{};
    g.position = l.position;
    g.type = uint32_t(l.type);
    g.direction = l.direction;
    g.range = l.range;
    g.intensity = l.intensity;
    g.cosInner = std::cos(l.innerConeAngle);
    g.cosOuter = std::cos(l.outerConeAngle);
    out.push_back(g);
  }
  return out;
}

uint32_t textureIndex(int32_t t) { return t >= 0 ? uint32_t(t) : gpu::NO_TEXTURE; }

}  // namespace

std::span<const Binding> sceneBindings(const Context& ctx) {
  return ctx.rayQuery ? std::span<const Binding>(kSceneBindings) : std::span<const Binding>(kSceneBindings).subspan(1);
}

namespace {

std::vector<BvhMesh> bvhMeshes(const Scene& scene) {
  std::vector<BvhMesh> meshes(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    for (uint32_t p = 0; p < scene.meshes[m].primitiveCount; ++p) {
      uint32_t id = scene.meshes[m].firstPrimitive + p;
      const Primitive& prim = scene.primitives[id];
      meshes[m].geometries.push_back({prim.firstIndex, prim.indexCount / 3, prim.vertexOffset, id});
    }
  return meshes;
}

std::vector<BvhInstance> bvhInstances(const Scene& scene, const std::vector<uint8_t>& forceMovable) {
  std::vector<BvhInstance> out;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    out.push_back({inst.mesh, inst.worldFromObject, inst.movable || (i < forceMovable.size() && forceMovable[i])});
  }
  return out;
}

template <typename T>
void writeMapped(Buffer& buffer, const std::vector<T>& data) {
  if (!data.empty()) std::memcpy(buffer.mapped, data.data(), std::min<size_t>(buffer.size, data.size() * sizeof(T)));
}

constexpr VkBufferUsageFlags kTexels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;

// The BVH arrays are read as RGBA32UI texel buffers: on lavapipe a texel fetch
// is much cheaper than a storage-buffer load with a per-lane address.
VkBufferView texelView(const Context& ctx, const Buffer& buffer, const char* what) {
  VkDeviceSize texels = buffer.size / 16;
  if (texels > ctx.properties.limits.maxTexelBufferElements)
    throw std::runtime_error(std::string("the compute BVH's ") + what + " need " + std::to_string(texels) +
                             " texels, more than the device's maxTexelBufferElements (" +
                             std::to_string(ctx.properties.limits.maxTexelBufferElements) + ")");
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.buffer;
  info.format = VK_FORMAT_R32G32B32A32_UINT;  // integers: ids and float bits pass unchanged
  info.range = VK_WHOLE_SIZE;
  VkBufferView view = VK_NULL_HANDLE;
  VK_CHECK(vkCreateBufferView(ctx.device, &info, nullptr, &view));
  return view;
}

void destroyBvhBuffers(const Context& ctx, SceneGpu& gpu) {
  for (VkBufferView* v : {&gpu.bvhNodesView, &gpu.bvhTrianglesView, &gpu.bvhTopNodesView, &gpu.bvhInstancesView}) {
    if (*v) vkDestroyBufferView(ctx.device, *v, nullptr);
    *v = VK_NULL_HANDLE;
  }
  for (Buffer* b : {&gpu.bvhNodes, &gpu.bvhTriangles, &gpu.bvhTopNodes, &gpu.bvhInstances}) destroyBuffer(ctx, *b);
}

// Builds the compute backend's BVH and uploads it (bottom levels device-local,
// the top level host-visible and sized for every instance).
void buildBvhBuffers(const Context& ctx, const Scene& scene, const std::vector<uint8_t>& forceMovable, SceneGpu& gpu) {
  std::vector<BvhMesh> meshes = bvhMeshes(scene);
  std::vector<BvhInstance> instances = bvhInstances(scene, forceMovable);
  gpu.bvh = buildSceneBvh({scene.positions, scene.indices, meshes, instances});
  destroyBvhBuffers(ctx, gpu);
  std::vector<gpu::GpuBvhNode> nodes = gpu.bvh.bottomNodes;
  if (nodes.empty()) nodes.push_back({});  // never referenced; a buffer may not be empty
  gpu.bvhNodes = upload(ctx, nodes, kTexels);
  std::vector<gpu::GpuBvhTriangle> triangles = gpu.bvh.triangles;
  if (triangles.empty()) triangles.push_back({});
  gpu.bvhTriangles = upload(ctx, triangles, kTexels);
  gpu.bvhTopNodes = createBuffer(ctx, maxTopNodes(scene.instances.size()) * sizeof(gpu::GpuBvhNode), kTexels,
                                 MemoryKind::HostVisible);
  gpu.bvhInstances = createBuffer(ctx, maxTopInstances(scene.instances.size()) * sizeof(gpu::GpuBvhInstance), kTexels,
                                  MemoryKind::HostVisible);
  writeMapped(gpu.bvhTopNodes, gpu.bvh.topNodes);
  writeMapped(gpu.bvhInstances, gpu.bvh.topInstances);
  gpu.bvhNodesView = texelView(ctx, gpu.bvhNodes, "nodes");
  gpu.bvhTrianglesView = texelView(ctx, gpu.bvhTriangles, "triangles");
  gpu.bvhTopNodesView = texelView(ctx, gpu.bvhTopNodes, "top-level nodes");
  gpu.bvhInstancesView = texelView(ctx, gpu.bvhInstances, "instances");
}

void writeBvhDescriptors(const Context& ctx, const SceneGpu& gpu) {
  DescriptorWriter w(gpu.set.set);
  w.uniformTexelBuffer(gpu::SCENE_BINDING_BVH_NODES, gpu.bvhNodesView)
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_TRIANGLES, gpu.bvhTrianglesView)
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_TOP_NODES, gpu.bvhTopNodesView)
      .uniformTexelBuffer(gpu::SCENE_BINDING_BVH_INSTANCES, gpu.bvhInstancesView);
  w.write(ctx.vk);
}

// The sky's constants, sampling tables and map (texture index = the scene's
// texture count: it is bound after them). A black sky, or a map of zeros,
// is no sky: SCENE_SPEC_HAS_SKY stays off.
void uploadSky(const Context& ctx, const Sky& sky, uint32_t textureCount, SceneGpu& gpu) {
  gpu::GpuSceneConstants& c = gpu.sceneConstants;
  c.skyRadiance = glm::vec3(0.0f);
  c.skyTexture = gpu::NO_TEXTURE;
  c.skySize = glm::uvec2(0);
  c.skyDistributionSum = 0.0f;
  std::vector<float> tables;
  if (sky.enabled() && sky.hasMap()) tables = skyDistribution(sky.map, c.skyDistributionSum);
  gpu.hasSky = sky.enabled() && (!sky.hasMap() || c.skyDistributionSum > 0.0f);
  if (gpu.hasSky) c.skyRadiance = sky.radiance;
  if (gpu.hasSky && sky.hasMap()) {
    c.skyTexture = textureCount;
    c.skySize = {sky.map.width, sky.map.height};
    std::vector<float> rgba(size_t(sky.map.width) * sky.map.height * 4, 1.0f);
    for (size_t p = 0; p < size_t(sky.map.width) * sky.map.height; ++p)
      for (size_t k = 0; k < 3; ++k) rgba[4 * p + k] = sky.map.pixels[p * sky.map.channels + k];
    gpu.skyMap = createImage(ctx, {sky.map.width, sky.map.height}, VK_FORMAT_R32G32B32A32_SFLOAT,
                             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    uploadImage(ctx, gpu.skyMap, rgba.data(), rgba.size() * sizeof(float), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  }
  const size_t bytes = std::max<size_t>(tables.size() * sizeof(float), 16);
  gpu.skyDistribution = createBuffer(ctx, bytes, kStorage, MemoryKind::HostVisible);
  if (!tables.empty()) std::memcpy(gpu.skyDistribution.mapped, tables.data(), tables.size() * sizeof(float));
}

}  // namespace

void createSceneGpu(const Context& ctx, const Scene& scene, SceneGpu& gpu) {
  gpu.positions = upload(ctx, scene.positions, kBuildInput);
  gpu.normals = upload(ctx, scene.normals, kStorage);
  gpu.uvs = upload(ctx, scene.uvs, kStorage);
  gpu.indices = upload(ctx, scene.indices, kBuildInput);

  std::vector<gpu::GpuGeometry> geometries;
  for (const Primitive& p : scene.primitives) geometries.push_back({p.firstIndex, p.vertexOffset, p.material, p.indexCount / 3});
  gpu.geometries = upload(ctx, geometries, kStorage);

  std::vector<gpu::GpuMaterial> materials;
  for (const Material& m : scene.materials) {
    gpu::GpuMaterial g{};
    g.baseColor = m.baseColor;
    g.emission = m.emission;
    g.metallic = m.metallic;
    g.roughness = m.roughness;
    g.alphaCutoff = m.alphaCutoff;
    g.baseColorTexture = textureIndex(m.baseColorTexture);
    g.metallicRoughnessTexture = textureIndex(m.metallicRoughnessTexture);
    g.emissiveTexture = textureIndex(m.emissiveTexture);
    g.flags = (m.needsGlossyLobe() ? gpu::MATERIAL_FLAG_GLOSSY : 0u) |
              (m.alphaMode == AlphaMode::Mask ? gpu::MATERIAL_FLAG_ALPHA_MASK : 0u) |
              (m.isEmissive() ? gpu::MATERIAL_FLAG_EMISSIVE : 0u);
    materials.push_back(g);
  }
  gpu.materials = upload(ctx, materials, kStorage);
  // Only materials some primitive uses decide which passes run (the loader
  // always appends the glTF default material, a metal, for primitives without one).
  std::vector<uint8_t> used(scene.materials.size(), 0);
  for (const Primitive& p : scene.primitives)
    if (p.material < used.size()) used[p.material] = 1;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    gpu.hasAlphaMask |= scene.materials[i].alphaMode == AlphaMode::Mask;
    gpu.hasGlossyMaterials |= scene.materials[i].needsGlossyLobe();
  }

  std::vector<gpu::GpuInstance> instances = gpuInstances(scene, {});
  gpu.instances = createBuffer(ctx, instances.size() * sizeof(gpu::GpuInstance), kStorage, MemoryKind::HostVisible);
  if (!instances.empty()) std::memcpy(gpu.instances.mapped, instances.data(), instances.size() * sizeof(gpu::GpuInstance));
  for (const Instance& inst : scene.instances) gpu.previousTransforms.push_back(inst.worldFromObject);

  float totalPower = 0.0f;
  std::vector<gpu::GpuEmissiveTriangle> emissive = emissiveTable(scene, totalPower);
  gpu.emissiveTriangles = createBuffer(ctx, emissive.size() * sizeof(gpu::GpuEmissiveTriangle), kStorage, MemoryKind::HostVisible);
  if (!emissive.empty()) std::memcpy(gpu.emissiveTriangles.mapped, emissive.data(), emissive.size() * sizeof(emissive[0]));
  std::vector<gpu::GpuPunctualLight> lights = punctualLights(scene);  // host-visible: lights may move
  gpu.punctualLights = createBuffer(ctx, std::max<size_t>(lights.size(), 1) * sizeof(gpu::GpuPunctualLight), kStorage,
                                    MemoryKind::HostVisible);
  if (!lights.empty()) std::memcpy(gpu.punctualLights.mapped, lights.data(), lights.size() * sizeof(lights[0]));

  Bounds bounds = scene.worldBounds();
  gpu::GpuSceneConstants& c = gpu.sceneConstants;
  c.emissiveTriangleCount = uint32_t(emissive.size());
  c.punctualLightCount = uint32_t(lights.size());
  c.emissiveTotalPower = totalPower;
  c.sceneExtent = std::max(bounds.extent(), 1e-6f);
  // A rough scale of the radiance the scene will hold: a grey (0.5) surface a
  // quarter of the scene away from the brightest punctual light, or a tenth
  // of the brightest emission. Only its order of magnitude matters.
  float typical = 0.0f;
  float quarter = 0.25f * c.sceneExtent;
  for (const PunctualLight& l : scene.lights)
    typical = std::max(typical, luminance(l.intensity) / (quarter * quarter) * 0.5f / 3.14159265f);
  for (const Material& m : scene.materials) typical = std::max(typical, 0.1f * luminance(m.emission));
  typical = std::max(typical, 0.5f * luminance(scene.sky.radiance) * (scene.sky.hasMap() ? meanLuminance(scene.sky.map) : 1.0f));
  gpu.typicalRadiance = typical > 0.0f && std::isfinite(typical) ? typical : 1.0f;
  c.boundsMin = bounds.empty() ? glm::vec3(0.0f) : bounds.min;
  c.boundsMax = bounds.empty() ? glm::vec3(0.0f) : bounds.max;
  uploadSky(ctx, scene.sky, uint32_t(std::max<size_t>(scene.textures.size(), 1)), gpu);  // after the textures below
  gpu.constants = createBuffer(ctx, sizeof(c), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryKind::HostVisible);
  std::memcpy(gpu.constants.mapped, &c, sizeof(c));

  // Textures with full mip chains; a white texel stands in when there are none.
  std::vector<Texture> fallback;
  if (scene.textures.empty()) fallback.push_back({"white", 1, 1, {255, 255, 255, 255}, false});
  const std::vector<Texture>& textures = scene.textures.empty() ? fallback : scene.textures;
  for (const Texture& t : textures) {
    uint32_t mips = 1 + uint32_t(std::floor(std::log2(double(std::max(t.width, t.height)))));
    Image img = createImage(ctx, {t.width, t.height}, t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM,
                            VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                            mips);
    uploadImageWithMips(ctx, img, t.rgba8.data(), t.rgba8.size());
    gpu.textures.push_back(img);
  }
  VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  samplerInfo.magFilter = VK_FILTER_LINEAR;
  samplerInfo.minFilter = VK_FILTER_LINEAR;
  samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  samplerInfo.maxLod = VK_LOD_CLAMP_NONE;
  VK_CHECK(vkCreateSampler(ctx.device, &samplerInfo, nullptr, &gpu.sampler));

  gpu.traversal = ctx.traversalId();
  if (ctx.rayQuery) buildSceneAcceleration(ctx, scene, gpu.positions, gpu.indices, gpu.accel);
  buildBvhBuffers(ctx, scene, {}, gpu);

  gpu.set = createDescriptorSet(ctx, sceneBindings(ctx), uint32_t(gpu.textures.size()) + (gpu.skyMap.image ? 1u : 0u));
  writeBvhDescriptors(ctx, gpu);
  DescriptorWriter w(gpu.set.set);
  if (ctx.rayQuery) w.accelerationStructure(gpu::SCENE_BINDING_TLAS, &gpu.accel.tlas.handle);
  w.buffer(gpu::SCENE_BINDING_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.positions.buffer)
      .buffer(gpu::SCENE_BINDING_NORMALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.normals.buffer)
      .buffer(gpu::SCENE_BINDING_UVS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.uvs.buffer)
      .buffer(gpu::SCENE_BINDING_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.indices.buffer)
      .buffer(gpu::SCENE_BINDING_GEOMETRIES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.geometries.buffer)
      .buffer(gpu::SCENE_BINDING_INSTANCES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.instances.buffer)
      .buffer(gpu::SCENE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.materials.buffer)
      .buffer(gpu::SCENE_BINDING_EMISSIVE_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.emissiveTriangles.buffer)
      .buffer(gpu::SCENE_BINDING_PUNCTUAL_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.punctualLights.buffer)
      .buffer(gpu::SCENE_BINDING_CONSTANTS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, gpu.constants.buffer)
      .buffer(gpu::SCENE_BINDING_SKY_DISTRIBUTION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gpu.skyDistribution.buffer);
  for (uint32_t t = 0; t < gpu.textures.size(); ++t)
    w.sampledImage(gpu::SCENE_BINDING_TEXTURES, gpu.textures[t].view, gpu.sampler, t);
  if (gpu.skyMap.image)
    w.sampledImage(gpu::SCENE_BINDING_TEXTURES, gpu.skyMap.view, gpu.sampler, gpu.sceneConstants.skyTexture);
  w.write(ctx.vk);
}

void recordSceneTransformUpdate(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu) {
  std::vector<gpu::GpuInstance> instances = gpuInstances(scene, gpu.previousTransforms);
  if (!instances.empty()) std::memcpy(gpu.instances.mapped, instances.data(), instances.size() * sizeof(gpu::GpuInstance));
  for (size_t i = 0; i < scene.instances.size(); ++i) gpu.previousTransforms[i] = scene.instances[i].worldFromObject;
  float totalPower = 0.0f;
  std::vector<gpu::GpuEmissiveTriangle> emissive = emissiveTable(scene, totalPower);
  // Moving instances keep their triangle count; only degenerate scaling could drop entries.
  size_t count = std::min<size_t>(emissive.size(), gpu.sceneConstants.emissiveTriangleCount);
  if (count > 0) std::memcpy(gpu.emissiveTriangles.mapped, emissive.data(), count * sizeof(emissive[0]));
  gpu.sceneConstants.emissiveTriangleCount = uint32_t(count);
  gpu.sceneConstants.emissiveTotalPower = totalPower;
  std::memcpy(gpu.constants.mapped, &gpu.sceneConstants, sizeof(gpu.sceneConstants));
  std::vector<gpu::GpuPunctualLight> lights = punctualLights(scene);
  if (!lights.empty() && lights.size() == gpu.sceneConstants.punctualLightCount)
    std::memcpy(gpu.punctualLights.mapped, lights.data(), lights.size() * sizeof(lights[0]));
  std::vector<BvhInstance> bvhPlaced = bvhInstances(scene, {});
  std::vector<uint8_t> moved(scene.instances.size(), 0);
  bool mergedMoved = false;
  for (size_t i = 0; i < scene.instances.size() && i < gpu.bvh.merged.size(); ++i) {
    moved[i] = gpu.bvh.merged[i] && scene.instances[i].worldFromObject != gpu.bvh.mergedTransforms[i];
    mergedMoved |= moved[i] != 0;
  }
  if (mergedMoved) {  // it was merged as static: take it out, once (the caller guarantees the GPU is done with set 0)
    buildBvhBuffers(ctx, scene, moved, gpu);
    writeBvhDescriptors(ctx, gpu);
  } else {
    rebuildTopLevel(bvhPlaced, gpu.bvh);
    writeMapped(gpu.bvhTopNodes, gpu.bvh.topNodes);
    writeMapped(gpu.bvhInstances, gpu.bvh.topInstances);
  }
  if (ctx.rayQuery) recordTlasRebuild(ctx, cmd, scene, gpu.accel);
}

void destroySceneGpu(const Context& ctx, SceneGpu& gpu) {
  destroyBvhBuffers(ctx, gpu);
  destroyDescriptorSet(ctx, gpu.set);
  destroySceneAcceleration(ctx, gpu.accel);
  for (Image& img : gpu.textures) destroyImage(ctx, img);
  if (gpu.skyMap.image) destroyImage(ctx, gpu.skyMap);
  if (gpu.sampler) vkDestroySampler(ctx.device, gpu.sampler, nullptr);
  for (Buffer* b : {&gpu.positions, &gpu.normals, &gpu.uvs, &gpu.indices, &gpu.geometries, &gpu.materials, &gpu.instances,
                    &gpu.emissiveTriangles, &gpu.punctualLights, &gpu.constants, &gpu.skyDistribution})
    destroyBuffer(ctx, *b);
  gpu = SceneGpu{};
}

}  // namespace engine
