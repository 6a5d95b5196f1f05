// The scene uploaded for the GPU: geometry pools, materials, textures, light
// tables, acceleration structures and the set-0 descriptor set that every
// pass binds (layout in shaders/shared/gpu_scene.h).
#pragma once
#include <array>

#include "acceleration.h"
#include "bvh_builder.h"
#include "descriptors.h"
#include "scene.h"

#include "shared/gpu_scene.h"

namespace engine {

struct SceneGpu {
  Buffer positions, normals, uvs, indices;
  Buffer geometries, materials;
  Buffer instances;          // host-visible GpuInstance[], rewritten on transform updates
  Buffer emissiveTriangles;  // host-visible; a 16-byte placeholder when the scene has none
  Buffer punctualLights;     // a 16-byte placeholder when the scene has none
  Buffer constants;          // host-visible GpuSceneConstants
  std::vector<Image> textures;  // at least one (a white texel) so the array is never empty
  Image skyMap;              // rgba32f equirectangular sky, bound after `textures` (none without a map)
  Buffer skyDistribution;    // its sampling tables; a 16-byte placeholder without a map
  VkSampler sampler = VK_NULL_HANDLE;
  SceneAcceleration accel;   // ray queries' BLAS/TLAS, only where ctx.rayQuery
  SceneBvh bvh;              // the compute backend's two-level BVH, always built
  Buffer bvhNodes, bvhTriangles;   // bottom levels, device-local
  Buffer bvhTopNodes, bvhInstances;  // top level, host-visible, sized for every instance
  VkBufferView bvhNodesView = VK_NULL_HANDLE, bvhTrianglesView = VK_NULL_HANDLE;  // RGBA32UI texel views of the four
  VkBufferView bvhTopNodesView = VK_NULL_HANDLE, bvhInstancesView = VK_NULL_HANDLE;
  DescriptorSet set;
  gpu::GpuSceneConstants sceneConstants{};
  std::vector<glm::mat4> previousTransforms;  // per instance, for motion vectors

  bool hasEmissiveTriangles() const { return sceneConstants.emissiveTriangleCount > 0; }
  bool hasPunctualLights() const { return sceneConstants.punctualLightCount > 0; }
  uint32_t traversal = gpu::TRAVERSAL_COMPUTE;  // how its users trace (ctx.traversalId() at creation)
  bool hasAlphaMask = false;  // some material uses alphaMode MASK
  bool hasGlossyMaterials = false;  // some material has a GGX lobe (MATERIAL_FLAG_GLOSSY)
  float typicalRadiance = 1.0f;     // W/(sr·m²), rough: a grey surface lit by the brightest light (see scene_gpu.cpp)
  bool hasSky = false;              // rays that leave the scene see light (Scene::sky)

  // Values for the SCENE_SPEC_* specialisation constants.
  std::array<uint32_t, SCENE_SPEC_COUNT> specialization() const {
    return {hasEmissiveTriangles() ? 1u : 0u, hasPunctualLights() ? 1u : 0u, hasAlphaMask ? 1u : 0u, hasSky ? 1u : 0u};
  }
};

// Expects a scene already Morton-sorted (mortonSortScene). Uploads and builds; waits.
void createSceneGpu(const Context& ctx, const Scene& scene, SceneGpu& gpu);
void destroySceneGpu(const Context& ctx, SceneGpu& gpu);

// For moving instances and lights: rewrites transforms, the emissive table
// and the punctual lights from `scene`, rebuilds the compute BVH's top level
// and records a TLAS rebuild into `cmd`. An instance that moves without
// Instance::movable set costs one rebuild of the BVH's bottom levels. The caller must ensure the
// previous frame's GPU work has finished (the buffers are host-written).
void recordSceneTransformUpdate(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu);

// The set-0 bindings, for pipelines that use the scene (binding 0, the TLAS,
// only where the device has ray queries enabled).
std::span<const Binding> sceneBindings(const Context& ctx);

}  // namespace engine
