#include "scene/acceleration.h"

#include <algorithm>
#include <cstring>

namespace gi {
namespace {

constexpr VkBufferUsageFlags kAddressable = VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkAccessFlags2 kAsReadWrite =
    VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR;

vk::Status createAs(vk::Device& d, VkAccelerationStructureTypeKHR type, VkDeviceSize size, AccelerationStructure& as) {
  GI_TRY(vk::createBuffer(d, size, VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | kAddressable, false,
                          as.storage));
  VkAccelerationStructureCreateInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  info.buffer = as.storage.buffer;
  info.size = size;
  info.type = type;
  GI_VK(d.fn.vkCreateAccelerationStructureKHR(d.device, &info, d.allocator, &as.handle));
  VkAccelerationStructureDeviceAddressInfoKHR addr{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  addr.accelerationStructure = as.handle;
  as.address = d.fn.vkGetAccelerationStructureDeviceAddressKHR(d.device, &addr);
  return {};
}

void destroyAs(vk::Device& d, AccelerationStructure& as) {
  if (as.handle) d.fn.vkDestroyAccelerationStructureKHR(d.device, as.handle, d.allocator);
  vk::destroyBuffer(d, as.storage);
  as = AccelerationStructure{};
}

VkDeviceAddress alignUp(VkDeviceAddress v, VkDeviceSize a) { return a > 1 ? (v + a - 1) / a * a : v; }

VkTransformMatrixKHR toVk(const glm::mat4& m) {
  VkTransformMatrixKHR t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.matrix[r][c] = m[c][r];
  return t;
}

// The TLAS's single geometry: the instance buffer.
VkAccelerationStructureGeometryKHR instancesGeometry(VkDeviceAddress instances) {
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.data.deviceAddress = instances;
  return g;
}

VkAccelerationStructureBuildGeometryInfoKHR buildInfo(VkAccelerationStructureTypeKHR type,
                                                      std::span<const VkAccelerationStructureGeometryKHR> geometries,
                                                      bool updatable = false) {
  VkAccelerationStructureBuildGeometryInfoKHR b{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  b.type = type;
  b.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
            (updatable ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR : 0);
  b.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  b.geometryCount = uint32_t(geometries.size());
  b.pGeometries = geometries.data();
  return b;
}

// A mesh's BLAS geometries: one per primitive, over the scene's packed positions and indices.
void blasGeometries(const AccelerationMesh& mesh, VkDeviceAddress positions, VkDeviceAddress indices,
                    std::vector<VkAccelerationStructureGeometryKHR>& geometries,
                    std::vector<VkAccelerationStructureBuildRangeInfoKHR>& ranges) {
  for (const AccelerationGeometry& geo : mesh.geometries) {
    VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.flags = geo.opaque ? VkGeometryFlagsKHR(VK_GEOMETRY_OPAQUE_BIT_KHR) : VkGeometryFlagsKHR(0);
    auto& tri = g.geometry.triangles;
    tri.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    tri.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    tri.vertexData.deviceAddress = positions + VkDeviceSize(geo.vertexOffset) * sizeof(glm::vec3);
    tri.vertexStride = sizeof(glm::vec3);
    tri.maxVertex = geo.vertexCount > 0 ? geo.vertexCount - 1 : 0;
    tri.indexType = VK_INDEX_TYPE_UINT32;
    tri.indexData.deviceAddress = indices + VkDeviceSize(geo.firstIndex) * sizeof(uint32_t);
    geometries.push_back(g);
    ranges.push_back({geo.triangleCount, 0, 0, 0});
  }
}

}  // namespace

void recordBlasUpdate(const vk::Device& d, VkCommandBuffer cmd, const vk::Buffer& positions, const vk::Buffer& indices,
                      const AccelerationMesh& mesh, const SceneAcceleration& accel, uint32_t m, bool rebuild) {
  std::vector<VkAccelerationStructureGeometryKHR> geometries;
  std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
  blasGeometries(mesh, deviceAddress(d, positions), deviceAddress(d, indices), geometries, ranges);
  VkAccelerationStructureBuildGeometryInfoKHR build =
      buildInfo(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, geometries, true);
  build.mode =
      rebuild ? VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR : VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR;
  build.srcAccelerationStructure = rebuild ? VK_NULL_HANDLE : accel.blas[m].handle;
  build.dstAccelerationStructure = accel.blas[m].handle;
  build.scratchData.deviceAddress = alignUp(deviceAddress(d, accel.updateScratch), accel.scratchAlignment);
  const VkAccelerationStructureBuildRangeInfoKHR* rangePointer = ranges.data();
  // Earlier traces read this BLAS; the update overwrites it in place.
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR,
                    VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite);
  d.fn.vkCmdBuildAccelerationStructuresKHR(cmd, 1, &build, &rangePointer);
  // The TLAS rebuild reads it; the next update reuses the scratch.
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite,
                    VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite);
}

VkDeviceAddress deviceAddress(const vk::Device& d, const vk::Buffer& buffer) {
  VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  info.buffer = buffer.buffer;
  return d.fn.vkGetBufferDeviceAddress(d.device, &info);
}

vk::Status buildSceneAcceleration(vk::Device& d, VkCommandBuffer cmd, const vk::Buffer& positions,
                                  const vk::Buffer& indices, std::span<const AccelerationMesh> meshes,
                                  std::span<const AccelerationInstance> instances, SceneAcceleration& accel,
                                  vk::Buffer& scratchOut) {
  VkPhysicalDeviceAccelerationStructurePropertiesKHR asProps{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &asProps;
  d.fn.vkGetPhysicalDeviceProperties2(d.physicalDevice, &props);
  accel.scratchAlignment = asProps.minAccelerationStructureScratchOffsetAlignment;
  const VkDeviceAddress positionsAddress = deviceAddress(d, positions), indicesAddress = deviceAddress(d, indices);

  // BLAS: size every mesh, one scratch big enough for the largest, build one by one.
  struct Pending {
    std::vector<VkAccelerationStructureGeometryKHR> geometries;
    std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  };
  std::vector<Pending> pending(meshes.size());
  VkDeviceSize maxScratch = 0, maxUpdateScratch = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    Pending& p = pending[m];
    std::vector<uint32_t> maxPrims;
    blasGeometries(meshes[m], positionsAddress, indicesAddress, p.geometries, p.ranges);
    for (const AccelerationGeometry& geo : meshes[m].geometries) maxPrims.push_back(geo.triangleCount);
    VkAccelerationStructureBuildGeometryInfoKHR build =
        buildInfo(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, p.geometries, meshes[m].updatable);
    d.fn.vkGetAccelerationStructureBuildSizesKHR(d.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build,
                                                 maxPrims.data(), &p.sizes);
    maxScratch = std::max(maxScratch, p.sizes.buildScratchSize);
    if (meshes[m].updatable)  // updates, and the rebuilds of a degraded one (gi::SceneCreateDesc::rebuildCostRatio)
      maxUpdateScratch = std::max({maxUpdateScratch, p.sizes.updateScratchSize, p.sizes.buildScratchSize});
  }
  GI_TRY(vk::createBuffer(d, maxScratch + accel.scratchAlignment, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | kAddressable,
                          false, scratchOut));
  if (maxUpdateScratch > 0)
    GI_TRY(vk::createBuffer(d, maxUpdateScratch + accel.scratchAlignment,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | kAddressable, false, accel.updateScratch));
  const VkDeviceAddress scratch = alignUp(deviceAddress(d, scratchOut), accel.scratchAlignment);
  accel.blas.resize(meshes.size());
  for (size_t m = 0; m < meshes.size(); ++m) {
    Pending& p = pending[m];
    GI_TRY(
        createAs(d, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, p.sizes.accelerationStructureSize, accel.blas[m]));
    VkAccelerationStructureBuildGeometryInfoKHR build =
        buildInfo(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, p.geometries, meshes[m].updatable);
    build.dstAccelerationStructure = accel.blas[m].handle;
    build.scratchData.deviceAddress = scratch;
    const VkAccelerationStructureBuildRangeInfoKHR* ranges = p.ranges.data();
    d.fn.vkCmdBuildAccelerationStructuresKHR(cmd, 1, &build, &ranges);
    // The scratch buffer is reused by the next build; the TLAS build reads this BLAS.
    vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite,
                      VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite);
  }

  // TLAS: sized once for the instance count; rebuilt in place on every update.
  accel.instanceCount = uint32_t(instances.size());
  GI_TRY(vk::createBuffer(d, std::max<size_t>(1, accel.instanceCount) * sizeof(VkAccelerationStructureInstanceKHR),
                          VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | kAddressable |
                              VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          true, accel.instanceBuffer));
  VkAccelerationStructureGeometryKHR g = instancesGeometry(deviceAddress(d, accel.instanceBuffer));
  VkAccelerationStructureBuildGeometryInfoKHR build =
      buildInfo(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, std::span(&g, 1));
  VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  d.fn.vkGetAccelerationStructureBuildSizesKHR(d.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build,
                                               &accel.instanceCount, &sizes);
  GI_TRY(createAs(d, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, sizes.accelerationStructureSize, accel.tlas));
  GI_TRY(vk::createBuffer(d, sizes.buildScratchSize + accel.scratchAlignment,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | kAddressable, false, accel.tlasScratch));
  const std::vector<VkAccelerationStructureInstanceKHR> placed = tlasInstances(instances, accel);
  std::memcpy(accel.instanceBuffer.memory.mapped, placed.data(),
              placed.size() * sizeof(placed[0]));  // before any frame
  recordTlasRebuild(d, cmd, accel);
  return {};
}

std::vector<VkAccelerationStructureInstanceKHR> tlasInstances(std::span<const AccelerationInstance> instances,
                                                              const SceneAcceleration& accel) {
  std::vector<VkAccelerationStructureInstanceKHR> out(accel.instanceCount);
  for (uint32_t i = 0; i < accel.instanceCount; ++i) {
    VkAccelerationStructureInstanceKHR& vi = out[i];
    vi.transform = toVk(instances[i].worldFromObject);
    vi.instanceCustomIndex = instances[i].index;
    vi.mask = 0xff;
    // Surfaces are lit from both sides; only emission is one-sided (decided in the shader).
    vi.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
    vi.accelerationStructureReference = accel.blas[instances[i].mesh].address;
  }
  return out;
}

void writeTlasInstances(const vk::Device& d, VkCommandBuffer cmd, std::span<const AccelerationInstance> instances,
                        const SceneAcceleration& accel) {
  const std::vector<VkAccelerationStructureInstanceKHR> placed = tlasInstances(instances, accel);
  vk::recordBufferWrite(d, cmd, accel.instanceBuffer, placed.data(), placed.size() * sizeof(placed[0]));
}

void recordTlasRebuild(const vk::Device& d, VkCommandBuffer cmd, SceneAcceleration& accel) {
  VkAccelerationStructureGeometryKHR g = instancesGeometry(deviceAddress(d, accel.instanceBuffer));
  VkAccelerationStructureBuildGeometryInfoKHR build =
      buildInfo(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, std::span(&g, 1));
  build.dstAccelerationStructure = accel.tlas.handle;
  build.scratchData.deviceAddress = alignUp(deviceAddress(d, accel.tlasScratch), accel.scratchAlignment);
  VkAccelerationStructureBuildRangeInfoKHR range{accel.instanceCount, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
  // Earlier traces (the previous frame's) must be done before the rebuild overwrites the TLAS.
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR,
                    VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, kAsReadWrite);
  d.fn.vkCmdBuildAccelerationStructuresKHR(cmd, 1, &build, &ranges);
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                    VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                    VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
}

void destroySceneAcceleration(vk::Device& d, SceneAcceleration& accel) {
  for (AccelerationStructure& b : accel.blas) destroyAs(d, b);
  destroyAs(d, accel.tlas);
  vk::destroyBuffer(d, accel.tlasScratch);
  vk::destroyBuffer(d, accel.updateScratch);
  vk::destroyBuffer(d, accel.instanceBuffer);
  accel = SceneAcceleration{};
}

}  // namespace gi
