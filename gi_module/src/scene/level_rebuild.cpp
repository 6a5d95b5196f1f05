#include "scene/level_rebuild.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <future>
#include <memory>

namespace gi {
namespace {

// Installs a prepared level of mesh `mesh` into s.bvh and the ratio's base and, where the scene has a
// compute BVH, into the refit plan and the device's BVH, written in `cmd` (its nodes, its triangle slots,
// the refit order from its run on). The nodes come as built: the caller refits them to this update's pose.
void installPreparedLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh, PreparedLevel& p) {
  installMeshLevel(p.level, mesh, s.bvh);
  s.levelRebuilds++;
  s.builtCost[mesh] = p.cost;
  s.costParts[mesh] = std::move(p.costParts);
  s.refitCostRatio = 1.0f;             // as built
  if (!s.facts.hasComputeBvh) return;  // the measure's tree alone: the BLAS was built anew
  const size_t changed = replaceMeshRefit(s.refit, mesh, std::move(p.refit), p.order);
  const uint32_t root = s.bvh.meshRoot[mesh], first = s.bvh.meshFirstTriangle[mesh];
  vk::recordBufferWrite(s.gpu, cmd, s.bvhNodes, p.level.nodes.data(), p.level.nodes.size() * sizeof(gpu::GpuBvhNode),
                        root * sizeof(gpu::GpuBvhNode));
  vk::recordBufferWrite(s.gpu, cmd, s.bvhTriangles, p.level.triangles.data(),
                        p.level.triangles.size() * sizeof(gpu::GpuBvhTriangle), first * sizeof(gpu::GpuBvhTriangle));
  vk::recordBufferWrite(s.gpu, cmd, s.refitOrder, s.refit.order.data() + changed,
                        (s.refit.order.size() - changed) * sizeof(uint32_t), changed * sizeof(uint32_t));
}

// Mesh `mesh`'s level rebuilt from the positions in s.packed and prepared on a worker thread.
void startLevelRebuild(Scene& s, uint32_t mesh) {
  auto job = std::make_unique<Scene::LevelRebuildJob>();
  job->mesh = mesh;
  job->bvhBuilds = s.bvhBuilds;
  job->positions = s.packed.positions;  // the updates go on writing the scene's own
  job->meshes = bvhMeshes(s.packed);
  const BvhInput input{job->positions, s.packed.indices, job->meshes, {}};  // indices never change
  job->level = std::async(std::launch::async, prepareMeshLevel, input, mesh, meshLevelSlots(s.bvh, mesh));
  s.rebuildJob = std::move(job);
}

// The off-thread rebuild of `mesh`'s level, if it finished: installed and written in `cmd` (true), or
// dropped where it failed, found no room or was started before a whole-BVH build.
bool installFinishedRebuild(Scene& s, VkCommandBuffer cmd, uint32_t mesh) {
  Scene::LevelRebuildJob* job = s.rebuildJob.get();
  if (!job || job->mesh != mesh || job->level.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return false;
  PreparedLevel prepared;
  try {
    prepared = job->level.get();
  } catch (const std::exception&) {
    prepared = PreparedLevel{};
  }
  const bool current = job->bvhBuilds == s.bvhBuilds;
  s.rebuildJob.reset();
  if (!current || prepared.level.nodes.empty()) return false;
  installPreparedLevel(s, cmd, mesh, prepared);
  return true;
}

// The level measured on the positions in s.packed; past the ratio rebuilt here or started off thread.
LevelUpdate judgeLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh, const BvhInput& input) {
  // The measure walks every triangle (about 26 ns each here: 26 ms for a million, against the update's own
  // 6 ms), so a level of more than 64k triangles is measured a part at a time, 16k triangles an update: its
  // cost lags its deformation by up to n / 16k updates, as refits degrade it over frames (docs/RESULTS.md,
  // "Refit against rebuild").
  const uint32_t budget = s.bvh.meshTriangleCount[mesh] <= (1u << 16) ? UINT32_MAX : 1u << 14;
  const double ratio = meshLevelCostInParts(input, s.bvh, mesh, budget, s.costParts[mesh]) / s.builtCost[mesh];
  s.refitCostRatio = float(ratio);
  if (!(s.desc.rebuildCostRatio > 0.0f && ratio > s.desc.rebuildCostRatio)) return {};
  if (s.desc.rebuildOffThread) {
    if (s.rebuildJob) return {};  // one at a time: this level waits for a later update
    startLevelRebuild(s, mesh);
    return {false, true};
  }
  PreparedLevel prepared;
  try {
    prepared = prepareMeshLevel(input, mesh, meshLevelSlots(s.bvh, mesh));
  } catch (const std::exception&) {
    return {};  // Embree failed (memory): the refit goes on
  }
  if (prepared.level.nodes.empty()) return {};
  installPreparedLevel(s, cmd, mesh, prepared);
  return {true, true};
}

bool measured(const Scene& s, uint32_t mesh) { return mesh < s.builtCost.size() && s.builtCost[mesh] > 0.0; }

// Mesh `mesh`'s vertex ranges in the positions (12 bytes a vertex): each geometry's, packed one after
// another in the read-back buffer.
std::vector<VkBufferCopy> readbackRegions(const PackedScene& p, uint32_t mesh) {
  std::vector<VkBufferCopy> regions;
  VkDeviceSize packed = 0;
  for (uint32_t id = p.meshFirstGeometry[mesh]; id < p.meshFirstGeometry[mesh] + p.meshGeometryCount[mesh]; ++id) {
    const VkDeviceSize bytes = VkDeviceSize(p.geometryVertexCount[id]) * 12;
    regions.push_back({VkDeviceSize(p.geometries[id].vertexOffset) * 12, packed, bytes});
    packed += bytes;
  }
  return regions;
}

}  // namespace

LevelUpdate rebuildDegradedLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh) {
  if (!measured(s, mesh)) return {};
  if (installFinishedRebuild(s, cmd, mesh)) return {};  // built for an earlier pose: refit to this one
  const std::vector<BvhMesh> meshes = bvhMeshes(s.packed);
  return judgeLevel(s, cmd, mesh, {s.packed.positions, s.packed.indices, meshes, {}});
}

LevelUpdate followDeviceLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh) {
  if (!measured(s, mesh) || !s.positionsRead) return {};
  if (installFinishedRebuild(s, cmd, mesh)) return {};
  if (s.readbackMesh != mesh || s.gpu.fn.vkGetEventStatus(s.gpu.device, s.positionsRead) != VK_EVENT_SET) return {};
  // The copy completed (the event's dependency made it visible to the host): this mesh's positions as of
  // that update become the CPU's.
  const auto* bytes = static_cast<const char*>(s.positionsReadback.memory.mapped);
  for (const VkBufferCopy& r : readbackRegions(s.packed, mesh))
    std::memcpy(reinterpret_cast<char*>(s.packed.positions.data()) + r.srcOffset, bytes + r.dstOffset, r.size);
  s.gpu.fn.vkResetEvent(s.gpu.device, s.positionsRead);
  s.readbackMesh = UINT32_MAX;
  const std::vector<BvhMesh> meshes = bvhMeshes(s.packed);  // only on the updates that measure
  LevelUpdate level = judgeLevel(s, cmd, mesh, {s.packed.positions, s.packed.indices, meshes, {}});
  level.nodesBuilt = false;  // rebuilt here, for the read-back pose: refit to this update's
  return level;
}

void recordPositionsReadback(Scene& s, VkCommandBuffer cmd, uint32_t mesh) {
  if (!measured(s, mesh) || !s.positionsRead || s.readbackMesh != UINT32_MAX || s.rebuildJob) return;
  const std::vector<VkBufferCopy> regions = readbackRegions(s.packed, mesh);
  s.gpu.fn.vkCmdCopyBuffer(cmd, s.positions.buffer, s.positionsReadback.buffer, uint32_t(regions.size()),
                           regions.data());
  const VkMemoryBarrier2 toHost = vk::memoryBarrierInfo(VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                                        VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.memoryBarrierCount = 1;
  dependency.pMemoryBarriers = &toHost;
  s.gpu.fn.vkCmdSetEvent2(cmd, s.positionsRead, &dependency);
  s.readbackMesh = mesh;
}

vk::Status createPositionsReadback(Scene& s) {
  VkDeviceSize largest = 0;
  for (uint32_t m = 0; m < s.packed.meshDeformable.size(); ++m) {
    if (!s.packed.meshDeformable[m]) continue;
    VkDeviceSize bytes = 0;
    for (const VkBufferCopy& r : readbackRegions(s.packed, m)) bytes += r.size;
    largest = std::max(largest, bytes);
  }
  GI_TRY(vk::createBuffer(s.gpu, std::max<VkDeviceSize>(largest, 16), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true,
                          s.positionsReadback));
  VkEventCreateInfo info{VK_STRUCTURE_TYPE_EVENT_CREATE_INFO};
  if (VkResult r = s.gpu.fn.vkCreateEvent(s.gpu.device, &info, s.gpu.allocator, &s.positionsRead); r != VK_SUCCESS)
    return {r, "vkCreateEvent (the deformable meshes' read-back)"};
  return {};
}

void destroyPositionsReadback(Scene& s) {
  if (s.positionsRead) s.gpu.fn.vkDestroyEvent(s.gpu.device, s.positionsRead, s.gpu.allocator);
  s.positionsRead = VK_NULL_HANDLE;
  s.readbackMesh = UINT32_MAX;
  vk::destroyBuffer(s.gpu, s.positionsReadback);
}

}  // namespace gi
