#include "scene/refit.h"

#include <algorithm>
#include <cstddef>

#include "bvh_refit.comp.h"
#include "shared/bvh_refit.h"

namespace gi {
namespace {

gpu::RefitPush push(const RefitBuffers& b, uint32_t mode, uint32_t first, uint32_t count) {
  auto split = [](VkDeviceAddress a) { return glm::uvec2(uint32_t(a), uint32_t(a >> 32)); };
  gpu::RefitPush p{};
  p.positions = split(b.positions);
  p.indices = split(b.indices);
  p.geometries = split(b.geometries);
  p.triangles = split(b.triangles);
  p.nodes = split(b.nodes);
  p.order = split(b.order);
  p.topNodes = split(b.topNodes);
  p.topInstances = split(b.topInstances);
  p.mode = mode;
  p.first = first;
  p.count = count;
  return p;
}

// The refit's writes before every later reader of set 0's BVH views (traversal in any stage).
void afterRefit(const vk::Device& d, VkCommandBuffer cmd) {
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void dispatch(const vk::Device& d, VkCommandBuffer cmd, const vk::ComputeProgram& program, const gpu::RefitPush& p,
              uint32_t threads) {
  vk::dispatch(d, cmd, program, {}, {std::max(threads, 1u), 1}, p);
}

}  // namespace

MeshRefit meshRefit(const LevelArrays& level, uint32_t root, std::vector<uint32_t>& order) {
  MeshRefit refit;
  // Breadth first from the root: one list per depth.
  std::vector<std::vector<uint32_t>> depths{{root}};
  uint32_t firstTriangle = UINT32_MAX, endTriangle = 0;
  for (size_t depth = 0; depth < depths.size(); ++depth) {
    std::vector<uint32_t> next;
    for (uint32_t node : depths[depth]) {
      const gpu::GpuBvhNode& n = level.node(node);
      for (uint32_t ref : {n.child.x, n.child.y, n.child.z, n.child.w}) {
        if (ref == gpu::BVH_NO_CHILD) continue;
        if (ref & gpu::BVH_LEAF_BIT) {
          const uint32_t first = ref & gpu::BVH_LEAF_FIRST_MASK,
                         count = ((ref >> gpu::BVH_LEAF_COUNT_SHIFT) & 0xfu) + 1u;
          firstTriangle = std::min(firstTriangle, first);
          endTriangle = std::max(endTriangle, first + count);
        } else {
          next.push_back(ref);
        }
      }
    }
    if (!next.empty()) depths.push_back(std::move(next));
  }
  refit.firstTriangle = firstTriangle == UINT32_MAX ? 0 : firstTriangle;
  refit.triangleCount = endTriangle > refit.firstTriangle ? endTriangle - refit.firstTriangle : 0;
  for (size_t depth = depths.size(); depth-- > 0;) {
    refit.levels.emplace_back(uint32_t(order.size()), uint32_t(depths[depth].size()));
    order.insert(order.end(), depths[depth].begin(), depths[depth].end());
  }
  return refit;
}

RefitPlan refitPlan(const SceneBvh& bvh, std::span<const uint8_t> deformable) {
  RefitPlan plan;
  plan.meshes.resize(deformable.size());
  const LevelArrays level = levelArrays(bvh);
  for (size_t m = 0; m < deformable.size() && m < bvh.meshRoot.size(); ++m)
    if (deformable[m] && bvh.meshRoot[m] != gpu::BVH_NO_CHILD)
      plan.meshes[m] = meshRefit(level, bvh.meshRoot[m], plan.order);
  return plan;
}

size_t replaceMeshRefit(RefitPlan& plan, uint32_t mesh, MeshRefit refit, std::span<const uint32_t> order) {
  // The meshes' runs follow one another in mesh order: this one's starts where the last run before it ends.
  size_t start = 0;
  for (uint32_t m = 0; m < mesh; ++m)
    for (const auto& [first, count] : plan.meshes[m].levels) start = std::max<size_t>(start, size_t(first) + count);
  size_t oldCount = 0;
  for (const auto& level : plan.meshes[mesh].levels) oldCount += level.second;
  plan.order.erase(plan.order.begin() + std::ptrdiff_t(start), plan.order.begin() + std::ptrdiff_t(start + oldCount));
  plan.order.insert(plan.order.begin() + std::ptrdiff_t(start), order.begin(), order.end());
  for (auto& level : refit.levels) level.first += uint32_t(start);
  const int64_t shift = int64_t(order.size()) - int64_t(oldCount);
  for (size_t m = mesh + 1; m < plan.meshes.size(); ++m)
    for (auto& level : plan.meshes[m].levels) level.first = uint32_t(int64_t(level.first) + shift);
  plan.meshes[mesh] = std::move(refit);
  return start;
}

vk::Status createRefitProgram(const vk::Device& d, vk::ComputeProgram& out) {
  return vk::createComputeProgram(d, spv_bvh_refit_comp, {}, sizeof(gpu::RefitPush), {REFIT_GROUP_SIZE, 1}, {}, out);
}

void recordMeshRefit(const vk::Device& d, VkCommandBuffer cmd, const vk::ComputeProgram& program,
                     const RefitBuffers& buffers, const RefitPlan& plan, uint32_t mesh) {
  const MeshRefit& refit = plan.meshes[mesh];
  dispatch(d, cmd, program, push(buffers, gpu::REFIT_TRIANGLES, refit.firstTriangle, refit.triangleCount),
           refit.triangleCount);
  for (const auto& [first, count] : refit.levels) {
    vk::computeToComputeBarrier(d, cmd);  // each level reads what the one below wrote
    dispatch(d, cmd, program, push(buffers, gpu::REFIT_NODES, first, count), count);
  }
  afterRefit(d, cmd);
}

void recordTopRefit(const vk::Device& d, VkCommandBuffer cmd, const vk::ComputeProgram& program,
                    const RefitBuffers& buffers, uint32_t topNodeCount) {
  // The top level's last writes (recorded copies, or a bottom refit) before its refit reads and rewrites it.
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  dispatch(d, cmd, program, push(buffers, gpu::REFIT_TOP, 0, topNodeCount), 1);
  afterRefit(d, cmd);
}

}  // namespace gi
