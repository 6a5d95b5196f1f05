#include "scene_gpu.h"

#include "skinning.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace engine {
namespace {

gi::InstanceDesc instanceDesc(const Instance& inst) {
  gi::InstanceDesc d;
  d.mesh = inst.mesh;
  std::memcpy(d.worldFromObject, &inst.worldFromObject[0][0], sizeof(d.worldFromObject));  // GLM: column-major
  d.movable = inst.movable;
  return d;
}

std::vector<gi::InstanceDesc> instanceDescs(const Scene& scene) {
  std::vector<gi::InstanceDesc> out;
  for (const Instance& inst : scene.instances) out.push_back(instanceDesc(inst));
  return out;
}

std::vector<gi::LightDesc> lightDescs(const Scene& scene) {
  std::vector<gi::LightDesc> out;
  for (const PunctualLight& l : scene.lights) {
    gi::LightDesc d;
    d.type = gi::LightType(uint32_t(l.type));
    for (int k = 0; k < 3; ++k) {
      d.position[k] = l.position[k];
      d.direction[k] = l.direction[k];
      d.intensity[k] = l.intensity[k];
    }
    d.range = l.range;
    d.innerConeAngle = l.innerConeAngle;
    d.outerConeAngle = l.outerConeAngle;
    out.push_back(d);
  }
  return out;
}

gi::MaterialDesc materialDesc(const Material& m) {
  gi::MaterialDesc d;
  for (int k = 0; k < 4; ++k) d.baseColor[k] = m.baseColor[k];
  for (int k = 0; k < 3; ++k) d.emissive[k] = m.emission[k];  // already × emissive_strength
  d.metallic = m.metallic;
  d.roughness = m.roughness;
  d.alphaMode = gi::AlphaMode(uint32_t(m.alphaMode));
  d.alphaCutoff = m.alphaCutoff;
  d.baseColorTexture = m.baseColorTexture;
  d.metallicRoughnessTexture = m.metallicRoughnessTexture;
  d.emissiveTexture = m.emissiveTexture;
  return d;
}

// A module error as the engine returns it: false, with the scene's file before the message.
bool failed(const gi::Error& e, const Scene& scene, std::string& error) {
  if (!e) return false;
  error = scene.sourcePath + ": " + e.message;
  return true;
}

}  // namespace

bool createSceneGpu(const Context& ctx, const Scene& scene, SceneGpu& gpu, std::string& error,
                    const gi::DeviceMemoryCallbacks& deviceMemory) {
  // Textures with full mip chains, the engine's; the module samples them.
  for (const Texture& t : scene.textures) {
    uint32_t mips = 1 + uint32_t(std::floor(std::log2(double(std::max(t.width, t.height)))));
    Image img = createImage(
        ctx, {t.width, t.height}, t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM,
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, error, mips);
    gpu.textures.push_back(img);
    uploadImageWithMips(ctx, img, t.rgba8.data(), t.rgba8.size(), error);
  }
  VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  samplerInfo.magFilter = VK_FILTER_LINEAR;
  samplerInfo.minFilter = VK_FILTER_LINEAR;
  samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  samplerInfo.maxLod = VK_LOD_CLAMP_NONE;
  if (error.empty())
    VK_SUCCEEDED(error, "the textures' sampler", vkCreateSampler(ctx.device, &samplerInfo, nullptr, &gpu.sampler));
  if (!error.empty()) {
    error = scene.sourcePath + ": " + error;
    destroySceneGpu(ctx, gpu);
    return false;
  }

  // The module numbers geometries mesh by mesh; the G-buffer draws by primitive index.
  std::vector<gi::MeshDesc> meshes;
  uint32_t next = 0;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.firstPrimitive != next) {
      error = scene.sourcePath + ": primitives are not numbered mesh by mesh (mesh " + mesh.name + ")";
      destroySceneGpu(ctx, gpu);
      return false;
    }
    next += mesh.primitiveCount;
  }
  std::vector<gi::PrimitiveDesc> primitives;
  for (const Primitive& p : scene.primitives)
    primitives.push_back({p.firstIndex, p.indexCount, p.vertexOffset, p.vertexCount, p.material});
  for (const Mesh& mesh : scene.meshes) {
    gi::MeshDesc d;
    d.positions = &scene.positions[0].x;
    d.normals = &scene.normals[0].x;
    d.uvs = scene.uvs.empty() ? nullptr : &scene.uvs[0].x;
    d.vertexCount = uint32_t(scene.positions.size());
    d.indices = scene.indices.data();
    d.indexCount = uint32_t(scene.indices.size());
    d.primitives = std::span(primitives).subspan(mesh.firstPrimitive, mesh.primitiveCount);
    d.deformable = mesh.deformable;
    meshes.push_back(d);
  }
  std::vector<gi::MaterialDesc> materials;
  for (const Material& m : scene.materials) materials.push_back(materialDesc(m));
  std::vector<gi::TextureDesc> textures;
  for (const Image& img : gpu.textures) textures.push_back({img.view, gpu.sampler});
  std::vector<gi::LightDesc> lights = lightDescs(scene);
  std::vector<gi::InstanceDesc> instances = instanceDescs(scene);
  gi::SceneContents contents;
  contents.meshes = meshes;
  contents.materials = materials;
  contents.textures = textures;
  contents.lights = lights;
  contents.instances = instances;
  for (int k = 0; k < 3; ++k) contents.sky.radiance[k] = scene.sky.radiance[k];
  if (scene.sky.hasMap()) {
    contents.sky.map = scene.sky.map.pixels.data();
    contents.sky.width = scene.sky.map.width;
    contents.sky.height = scene.sky.map.height;
    contents.sky.channels = scene.sky.map.channels;
  }

  gi::SceneCreateDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;  // volk's
  desc.instance = ctx.instance;
  desc.physicalDevice = ctx.physicalDevice;
  desc.device = ctx.device;
  // The structures of the context's traversal; both (either backend can trace it) where asked.
  desc.bothTraversals = scene.bothTraversals && ctx.rayQuery;
  desc.traversal = desc.bothTraversals ? gi::Traversal::RayQuery : gi::Traversal(ctx.traversalId());
  desc.lightSampler = scene.lightSampler;
  if (scene.rebuildCostRatio >= 0.0f) desc.rebuildCostRatio = scene.rebuildCostRatio;
  desc.rebuildOffThread = scene.rebuildOffThread;
  desc.lightTreeCut = scene.lightTreeCut;
  desc.deviceMemory = deviceMemory;
  gi::Error created;
  const bool submitted = submitAndWait(
      ctx, [&](VkCommandBuffer cmd) { created = gi::createScene(desc, contents, cmd, gpu.scene); }, error);
  // CPU meshes: finishing frees the staging and builds nothing.
  if (!submitted || failed(created, scene, error) || failed(gi::finishSceneUpload(gpu.scene), scene, error)) {
    if (!submitted) error = scene.sourcePath + ": " + error;
    destroySceneGpu(ctx, gpu);
    return false;
  }
  gpu.desc = gi::sceneDesc(gpu.scene);
  gpu.desc.traversal = gi::Traversal(ctx.traversalId());
  gpu.set.layout = gpu.desc.layout;
  gpu.set.set = gpu.desc.set;
  if (!createSkinningGpu(ctx, scene, gpu.skinning, error)) {
    error = scene.sourcePath + ": " + error;
    destroySceneGpu(ctx, gpu);
    return false;
  }
  return true;
}

bool recordSceneTransformUpdate(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu,
                                std::string& error) {
  return !failed(gi::updateInstances(gpu.scene, cmd, instanceDescs(scene)), scene, error) &&
         !failed(gi::updateLights(gpu.scene, cmd, lightDescs(scene)), scene, error) &&
         !failed(recordSkinning(ctx, cmd, scene, gpu), scene, error);
}

bool recordSceneHold(VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu, std::string& error) {
  if (failed(gi::updateInstances(gpu.scene, cmd, instanceDescs(scene)), scene, error)) return false;
  for (uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh)
    if (scene.meshes[mesh].deformable && failed(gi::holdMeshVertices(gpu.scene, cmd, mesh), scene, error)) return false;
  return true;
}

bool recordMeshVertexUpdate(VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu, uint32_t mesh, std::string& error) {
  gi::MeshVertices vertices;
  vertices.positions = &scene.positions[0].x;
  vertices.normals = &scene.normals[0].x;
  return !failed(gi::updateMeshVertices(gpu.scene, cmd, mesh, vertices), scene, error);
}

void destroySceneGpu(const Context& ctx, SceneGpu& gpu) {
  destroySkinningGpu(ctx, gpu.skinning);
  gi::destroyScene(gpu.scene);
  for (Image& img : gpu.textures) destroyImage(ctx, img);
  if (gpu.sampler) vkDestroySampler(ctx.device, gpu.sampler, nullptr);
  gpu = SceneGpu{};
}

}  // namespace engine
