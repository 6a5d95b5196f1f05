// gi::Scene's state: the packed scene on the CPU (kept for updates), its
// device buffers, the compute BVH and the ray-query acceleration structures,
// and set 0.
#pragma once
#include <future>
#include <memory>
#include <vector>

#include "gi/scene.h"
#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "scene/acceleration.h"
#include "scene/bvh_builder.h"
#include "scene/device_meshes.h"
#include "scene/prepared_level.h"
#include "scene/refit.h"
#include "scene/scene_tables.h"

namespace gi {

struct Scene {
  vk::Device gpu;
  SceneCreateDesc desc;
  PackedScene packed;
  std::vector<InstanceDesc> instances;        // as given, with the latest transforms
  std::vector<glm::mat4> previousTransforms;  // per instance: last update's, for motion vectors
  size_t lightCount = 0;

  vk::Buffer positions, normals, uvs, indices, geometries, materials;  // device-local, uploaded once
  vk::Buffer instanceTable, emissiveTriangles, punctualLights, constants, skyDistribution;  // host-visible: written
      // at create, then by commands in the engine's frames (updates)
  vk::Buffer previousPositions;   // deformable meshes: last frame's positions (else set 0 binds `positions`)
  VkBufferView arrayViews[12]{};  // texel views of the arrays above and the constants (bindings 1–10, 15, 16)
  vk::Image skyMap;               // rgba32f equirectangular map (none for a constant sky)
  VkSampler skySampler = VK_NULL_HANDLE;
  SceneBvh bvh;  // the compute traversal's two levels (ray queries alone: deformable levels, for their measure)
  vk::Buffer bvhNodes, bvhTriangles, bvhTopNodes, bvhInstances;
  VkBufferView bvhViews[4]{};             // RGBA32UI texel views of the four, in that order
  RefitPlan refit;                        // deformable meshes: their bottom levels' refit order
  std::vector<double> builtCost;          // per deformable mesh: its level's cost when last built
  std::vector<LevelCostParts> costParts;  // per deformable mesh: its refit level's cost, kept in parts
  float refitCostRatio = 0.0f;            // SceneInfo's
  uint32_t levelRebuilds = 0;             // SceneInfo's
  // A degraded level's rebuild on a worker thread (SceneCreateDesc::rebuildOffThread), one at a time: the
  // pose it started from, held here while Embree builds from it and the level is prepared
  // (scene/prepared_level.h); the first update of its mesh after it finished installs it. A whole-BVH build in between (bvhBuilds) makes its slots stale: it is dropped.
  struct LevelRebuildJob {
    uint32_t mesh = 0;
    uint32_t bvhBuilds = 0;
    std::vector<glm::vec3> positions;
    std::vector<BvhMesh> meshes;
    std::future<PreparedLevel> level;
  };
  std::unique_ptr<LevelRebuildJob> rebuildJob;
  uint32_t bvhBuilds = 0;  // buildSceneBvh calls so far
  // Device-stream meshes' positions on their way back for the measure (scene/level_rebuild.h): the
  // host-visible copy, the event set after it, and whose they are (UINT32_MAX: none on their way).
  vk::Buffer positionsReadback;
  VkEvent positionsRead = VK_NULL_HANDLE;
  uint32_t readbackMesh = UINT32_MAX;
  vk::Buffer refitOrder;                           // RefitPlan::order on the device
  vk::ComputeProgram refitProgram, gatherProgram;  // deformable meshes only
  SceneAcceleration accel;                         // ray queries only
  std::vector<AccelerationMesh> accelMeshes;
  std::vector<uint32_t> tlasOrder;  // instance indices in the TLAS's (Morton) order, fixed at create
  vk::DescriptorSets set;           // set 0, one set
  gpu::GpuSceneConstants sceneConstants{};
  SceneDesc facts;                  // what sceneDesc() returns
  std::vector<vk::Buffer> staging;  // freed by finishSceneUpload
  bool awaitingGeometry = false;    // device meshes: built by finishSceneUpload
  HeldContents held;                // the contents meanwhile
  DeviceMeshReadback readback;
};

// Set 0's bindings (binding 0, the TLAS, only for ray queries).
std::span<const vk::Binding> sceneBindings(bool rayQuery);

}  // namespace gi
