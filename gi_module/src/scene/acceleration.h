// Ray queries' acceleration structures for a Scene: one BLAS per mesh (one
// geometry per primitive), one TLAS over the instances, rebuilt in place when
// instances move. Conventions the shaders rely on (trace.glsl): a TLAS
// instance's custom index is its index in set 0's instance table (whose
// firstGeometry plus the ray query's geometry index is the scene's
// geometry), cull mask 0xff, facing culling off. TLAS instances may come in
// any order (Morton order: lavapipe's builder does not sort).
#pragma once
#include <glm/glm.hpp>

#include <span>
#include <vector>

#include "gi/vk/resources.h"

namespace gi {

struct AccelerationStructure {
  VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
  vk::Buffer storage;
  VkDeviceAddress address = 0;
};

struct SceneAcceleration {
  std::vector<AccelerationStructure> blas;  // per mesh
  vk::Buffer updateScratch;                 // for the updatable BLASes' updates and rebuilds (none without)
  AccelerationStructure tlas;
  vk::Buffer tlasScratch;
  vk::Buffer instanceBuffer;  // host-visible VkAccelerationStructureInstanceKHR[]
  uint32_t instanceCount = 0;
  VkDeviceSize scratchAlignment = 0;
};

struct AccelerationGeometry {
  uint32_t firstIndex = 0, triangleCount = 0, vertexOffset = 0, vertexCount = 0;
  bool opaque = true;  // false: alpha-masked, the trace loop tests the texture
};
struct AccelerationMesh {
  std::vector<AccelerationGeometry> geometries;
  bool updatable = false;  // a deformable mesh: built with ALLOW_UPDATE, refit by recordBlasUpdate
};
struct AccelerationInstance {
  uint32_t index = 0;  // in the instance table: the TLAS instance's custom index (24 bits)
  uint32_t mesh = 0;
  glm::mat4 worldFromObject{1.0f};
};

VkDeviceAddress deviceAddress(const vk::Device& device, const vk::Buffer& buffer);

// Records the BLAS builds and the first TLAS build into `cmd`. `positions`
// (vec3) and `indices` (uint32) hold the packed geometry, written before
// `cmd`'s builds by earlier commands made visible to acceleration-structure
// builds. The BLAS scratch buffer goes to `scratchOut`, to be freed once
// `cmd` completes.
vk::Status buildSceneAcceleration(vk::Device& device, VkCommandBuffer cmd, const vk::Buffer& positions,
                                  const vk::Buffer& indices, std::span<const AccelerationMesh> meshes,
                                  std::span<const AccelerationInstance> instances, SceneAcceleration& accel,
                                  vk::Buffer& scratchOut);
// Records the update of mesh `m`'s BLAS (updatable) to the positions now in `positions`, written before by
// commands made visible to acceleration-structure builds, or with `rebuild` its build anew in place; the
// TLAS rebuild that must follow reads it.
void recordBlasUpdate(const vk::Device& device, VkCommandBuffer cmd, const vk::Buffer& positions,
                      const vk::Buffer& indices, const AccelerationMesh& mesh, const SceneAcceleration& accel,
                      uint32_t m, bool rebuild = false);
// The TLAS's instance records for `instances` (as many as the TLAS was built for).
std::vector<VkAccelerationStructureInstanceKHR> tlasInstances(std::span<const AccelerationInstance> instances,
                                                              const SceneAcceleration& accel);
// Records the write of the instance records into `cmd` (vk::recordBufferWrite: between
// vk::beginBufferWrites and vk::endBufferWrites), for the rebuild that follows.
void writeTlasInstances(const vk::Device& device, VkCommandBuffer cmd, std::span<const AccelerationInstance> instances,
                        const SceneAcceleration& accel);
// Records a TLAS rebuild from the instance buffer, with barriers before
// (earlier traces) and after (later ray queries in any shader stage).
void recordTlasRebuild(const vk::Device& device, VkCommandBuffer cmd, SceneAcceleration& accel);
void destroySceneAcceleration(vk::Device& device, SceneAcceleration& accel);

}  // namespace gi
