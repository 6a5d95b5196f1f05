// Deformable meshes (gi::MeshDesc::deformable): the compute traversal's BVH
// refit on the device to new vertices (bvh_refit.comp). At create, each
// deformable mesh's bottom level is split into levels (nodes of equal depth,
// refit together, the deepest first) and its triangle slots found; an update
// records the triangles' rewrite, one dispatch per level and the top level's
// refit. The tree keeps the shape Embree gave it, until a degraded level is
// rebuilt (gi::SceneCreateDesc::rebuildCostRatio) and its plan re-derived.
#pragma once
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "scene/bvh_builder.h"

namespace gi {

struct MeshRefit {
  uint32_t firstTriangle = 0, triangleCount = 0;      // the bottom level's triangle slots
  std::vector<std::pair<uint32_t, uint32_t>> levels;  // (first, count) into RefitPlan::order, deepest first
};

struct RefitPlan {
  std::vector<MeshRefit> meshes;  // per mesh (empty levels: not deformable, or no bottom level of its own)
  std::vector<uint32_t> order;    // bottom node indices, level by level
};
// The plan for the meshes flagged in `deformable` (per mesh).
RefitPlan refitPlan(const SceneBvh& bvh, std::span<const uint8_t> deformable);
// One level's refit from `root` in `level`, its node indices appended to `order` (its levels index there).
MeshRefit meshRefit(const LevelArrays& level, uint32_t root, std::vector<uint32_t>& order);
// Mesh `mesh`'s refit replaced by a rebuilt level's (`refit`'s levels index `order` from 0): its run of the
// plan's order swapped for `order`, the later meshes' levels moved with it. Returns the first order entry
// that changed (the device's copy needs the entries from there on).
size_t replaceMeshRefit(RefitPlan& plan, uint32_t mesh, MeshRefit refit, std::span<const uint32_t> order);

// Device addresses of the buffers the refit reads and writes.
struct RefitBuffers {
  VkDeviceAddress positions = 0, indices = 0, geometries = 0, triangles = 0, nodes = 0, order = 0, topNodes = 0,
                  topInstances = 0;
};
vk::Status createRefitProgram(const vk::Device& device, vk::ComputeProgram& out);
// Records mesh `m`'s refit, its vertices written before by commands made visible to compute shaders; ends with
// a barrier after which every shader stage reads the BVH.
void recordMeshRefit(const vk::Device& device, VkCommandBuffer cmd, const vk::ComputeProgram& program,
                     const RefitBuffers& buffers, const RefitPlan& plan, uint32_t mesh);
// Records the top level's refit (`topNodeCount` nodes) from the bottom levels' roots, with the same barriers.
void recordTopRefit(const vk::Device& device, VkCommandBuffer cmd, const vk::ComputeProgram& program,
                    const RefitBuffers& buffers, uint32_t topNodeCount);

}  // namespace gi
