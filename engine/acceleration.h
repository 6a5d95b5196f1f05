// Ray-tracing acceleration structures: one BLAS per mesh (one geometry per
// primitive), one TLAS over the instances. The TLAS can be rebuilt every frame
// for moving instances; BLASes are built once.
#pragma once
#include "resources.h"
#include "scene.h"

namespace engine {

struct AccelerationStructure {
  VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
  Buffer storage;
  VkDeviceAddress address = 0;
};

struct SceneAcceleration {
  std::vector<AccelerationStructure> blas;  // per scene mesh
  AccelerationStructure tlas;
  Buffer tlasScratch;
  Buffer instanceBuffer;  // host-visible VkAccelerationStructureInstanceKHR[]
  uint32_t instanceCount = 0;
};

// `positions`/`indices` are the scene's device buffers (with device-address and
// build-input usage). Builds and waits.
void buildSceneAcceleration(const Context& ctx, const Scene& scene, const Buffer& positions, const Buffer& indices,
                            SceneAcceleration& accel);
// Writes the instance transforms and records a TLAS rebuild into `cmd`, with a
// barrier that makes the TLAS visible to later ray queries.
void recordTlasRebuild(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneAcceleration& accel);
void destroySceneAcceleration(const Context& ctx, SceneAcceleration& accel);

}  // namespace engine
