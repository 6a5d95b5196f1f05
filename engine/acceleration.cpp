#include "acceleration.h"

#include <cstring>

namespace engine {
namespace {

constexpr VkBufferUsageFlags kBuildInputUsage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

AccelerationStructure createAs(const Context& ctx, VkAccelerationStructureTypeKHR type, VkDeviceSize size) {
  AccelerationStructure as;
  as.storage = createBuffer(ctx, size,
                            VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                            MemoryKind::DeviceLocal);
  VkAccelerationStructureCreateInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  info.buffer = as.storage.buffer;
  info.size = size;
  info.type = type;
  VK_CHECK(vkCreateAccelerationStructureKHR(ctx.device, &info, nullptr, &as.handle));
  VkAccelerationStructureDeviceAddressInfoKHR addr{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  addr.accelerationStructure = as.handle;
  as.address = vkGetAccelerationStructureDeviceAddressKHR(ctx.device, &addr);
  return as;
}

void destroyAs(const Context& ctx, AccelerationStructure& as) {
  if (as.handle) vkDestroyAccelerationStructureKHR(ctx.device, as.handle, nullptr);
  destroyBuffer(ctx, as.storage);
  as = AccelerationStructure{};
}

VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

VkTransformMatrixKHR toVk(const glm::mat4& m) {
  VkTransformMatrixKHR t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.matrix[r][c] = m[c][r];
  return t;
}

}  // namespace

void buildSceneAcceleration(const Context& ctx, const Scene& scene, const Buffer& positions, const Buffer& indices,
                            SceneAcceleration& accel) {
  const VkDeviceSize scratchAlign = ctx.accelerationProperties.minAccelerationStructureScratchOffsetAlignment;
  // BLAS: size every mesh, allocate one scratch big enough for the largest, build one by one.
  struct Pending {
    std::vector<VkAccelerationStructureGeometryKHR> geometries;
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  };
  std::vector<Pending> pending(scene.meshes.size());
  VkDeviceSize maxScratch = 0;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    Pending& p = pending[m];
    std::vector<uint32_t> maxPrims;
    for (uint32_t i = 0; i < mesh.primitiveCount; ++i) {
      const Primitive& prim = scene.primitives[mesh.firstPrimitive + i];
      VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
      g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
      // Alpha-masked geometry is non-opaque so the trace loop can test the texture.
      g.flags = scene.materials[prim.material].alphaMode == AlphaMode::Mask ? VkGeometryFlagsKHR(0)
                                                                            : VkGeometryFlagsKHR(VK_GEOMETRY_OPAQUE_BIT_KHR);
      auto& tri = g.geometry.triangles;
      tri.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
      tri.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
      tri.vertexData.deviceAddress = positions.address + VkDeviceSize(prim.vertexOffset) * sizeof(glm::vec3);
      tri.vertexStride = sizeof(glm::vec3);
      tri.maxVertex = prim.vertexCount > 0 ? prim.vertexCount - 1 : 0;
      tri.indexType = VK_INDEX_TYPE_UINT32;
      tri.indexData.deviceAddress = indices.address + VkDeviceSize(prim.firstIndex) * sizeof(uint32_t);
      p.geometries.push_back(g);
      p.ranges.push_back({prim.indexCount / 3, 0, 0, 0});
      maxPrims.push_back(prim.indexCount / 3);
    }
    VkAccelerationStructureBuildGeometryInfoKHR build{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    build.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    build.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    build.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    build.geometryCount = uint32_t(p.geometries.size());
    build.pGeometries = p.geometries.data();
    vkGetAccelerationStructureBuildSizesKHR(ctx.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build,
                                            maxPrims.data(), &p.sizes);
    maxScratch = std::max(maxScratch, p.sizes.buildScratchSize);
  }
  Buffer scratch = createBuffer(ctx, maxScratch + scratchAlign,
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                MemoryKind::DeviceLocal);
  accel.blas.resize(scene.meshes.size());
  submitAndWait(ctx, [&](VkCommandBuffer cmd) {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
      Pending& p = pending[m];
      accel.blas[m] = createAs(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, p.sizes.accelerationStructureSize);
      VkAccelerationStructureBuildGeometryInfoKHR build{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
      build.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
      build.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
      build.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
      build.geometryCount = uint32_t(p.geometries.size());
      build.pGeometries = p.geometries.data();
      build.dstAccelerationStructure = accel.blas[m].handle;
      build.scratchData.deviceAddress = alignUp(scratch.address, scratchAlign);
      const VkAccelerationStructureBuildRangeInfoKHR* ranges = p.ranges.data();
      vkCmdBuildAccelerationStructuresKHR(cmd, 1, &build, &ranges);
      // The scratch buffer is reused by the next build.
      memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                    VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR,
                    VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                    VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    }
  });
  destroyBuffer(ctx, scratch);

  // TLAS: sized once for the instance count; rebuilt in place on every update.
  accel.instanceCount = uint32_t(scene.instances.size());
  accel.instanceBuffer = createBuffer(ctx, std::max<size_t>(1, accel.instanceCount) * sizeof(VkAccelerationStructureInstanceKHR),
                                      kBuildInputUsage, MemoryKind::HostVisible);
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.data.deviceAddress = accel.instanceBuffer.address;
  VkAccelerationStructureBuildGeometryInfoKHR build{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  build.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  build.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  build.geometryCount = 1;
  build.pGeometries = &g;
  VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  vkGetAccelerationStructureBuildSizesKHR(ctx.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build,
                                          &accel.instanceCount, &sizes);
  accel.tlas = createAs(ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, sizes.accelerationStructureSize);
  accel.tlasScratch = createBuffer(ctx, sizes.buildScratchSize + scratchAlign,
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                   MemoryKind::DeviceLocal);
  submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordTlasRebuild(ctx, cmd, scene, accel); });
}

void recordTlasRebuild(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneAcceleration& accel) {
  (void)ctx;
  auto* out = static_cast<VkAccelerationStructureInstanceKHR*>(accel.instanceBuffer.mapped);
  for (uint32_t i = 0; i < accel.instanceCount; ++i) {
    const Instance& inst = scene.instances[i];
    VkAccelerationStructureInstanceKHR vi{};
    vi.transform = toVk(inst.worldFromObject);
    vi.instanceCustomIndex = scene.meshes[inst.mesh].firstPrimitive;  // + geometry index = scene primitive
    vi.mask = 0xff;
    // Surfaces are lit from both sides; only emission is one-sided (decided in the shader).
    vi.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
    vi.accelerationStructureReference = accel.blas[inst.mesh].address;
    out[i] = vi;
  }
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.data.deviceAddress = accel.instanceBuffer.address;
  VkAccelerationStructureBuildGeometryInfoKHR build{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  build.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  build.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  build.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  build.geometryCount = 1;
  build.pGeometries = &g;
  build.dstAccelerationStructure = accel.tlas.handle;
  VkDeviceSize align = ctx.accelerationProperties.minAccelerationStructureScratchOffsetAlignment;
  build.scratchData.deviceAddress = (accel.tlasScratch.address + align - 1) / align * align;
  VkAccelerationStructureBuildRangeInfoKHR range{accel.instanceCount, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
  // Earlier traces of this frame's predecessor must be done before the rebuild overwrites the TLAS.
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR,
                VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
  vkCmdBuildAccelerationStructuresKHR(cmd, 1, &build, &ranges);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
}

void destroySceneAcceleration(const Context& ctx, SceneAcceleration& accel) {
  for (auto& b : accel.blas) destroyAs(ctx, b);
  destroyAs(ctx, accel.tlas);
  destroyBuffer(ctx, accel.tlasScratch);
  destroyBuffer(ctx, accel.instanceBuffer);
  accel = SceneAcceleration{};
}

}  // namespace engine
