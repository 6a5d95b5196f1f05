// The compute traversal backend's BVH (layout in shaders/shared/gpu_bvh.h),
// built on the CPU with Embree's SAH builder (rtcBuildBVH; bottom levels at
// high quality, with spatial splits of the triangles) into our own node format. Self-contained: triangles and instances in, node arrays out; no
// Vulkan, no engine scene, so it can move with scene ingestion.
//
// Two levels. Every static instance (`movable` false) with an identity
// transform goes into one merged bottom level in world space (overlapping
// meshes that a top level cannot separate, as in Sponza, then share one
// SAH tree); every other instance references its mesh's own bottom level,
// built once. The top level over instances is cheap and is rebuilt whenever
// transforms change.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "shared/gpu_bvh.h"

namespace gi {

struct BvhGeometry {
  uint32_t firstIndex = 0;  // into the index pool
  uint32_t triangleCount = 0;
  uint32_t vertexOffset = 0;  // added to every index
  uint32_t id = 0;            // the absolute geometry index hits report
};

struct BvhMesh {
  std::vector<BvhGeometry> geometries;
  // Refit in place (gi::MeshDesc::deformable): its own level is built without spatial splits (a refit box
  // holds whole triangles, so split fragments would only repeat them) and keeps room for a rebuild.
  bool deformable = false;
};

struct BvhInstance {
  uint32_t mesh = 0;
  glm::mat4 worldFromObject{1.0f};
  bool movable = false;  // may change its transform later: never merged
};

struct BvhInput {
  std::span<const glm::vec3> positions;  // object space
  std::span<const uint32_t> indices;
  std::span<const BvhMesh> meshes;
  std::span<const BvhInstance> instances;
};

struct SceneBvh {
  std::vector<gpu::GpuBvhNode> bottomNodes;  // every bottom level; node 0.. of each is its root
  std::vector<gpu::GpuBvhTriangle> triangles;
  std::vector<uint32_t> meshRoot;           // per mesh: root node, or BVH_NO_CHILD when no unmerged instance uses it
  std::vector<glm::vec3> meshMin, meshMax;  // per mesh: object-space bounds of its bottom level
  // Per mesh with a level of its own: its triangle slots, and the nodes from its root a rebuild may fill
  // (deformable meshes: half as many again as the first build made; others: as many as it made).
  std::vector<uint32_t> meshFirstTriangle, meshTriangleCount, meshNodeCapacity;
  uint32_t mergedRoot = gpu::BVH_NO_CHILD;  // the merged static level's root node
  glm::vec3 mergedMin{0.0f}, mergedMax{0.0f};
  std::vector<uint8_t> merged;              // per instance: 1 if in the merged level
  std::vector<glm::mat4> mergedTransforms;  // per instance: the transform it was merged with
  std::vector<gpu::GpuBvhNode> topNodes;    // node 0 is the root
  std::vector<gpu::GpuBvhInstance> topInstances;
  double bottomBuildMs = 0.0;  // wall time of the bottom levels (paid once)
  double topBuildMs = 0.0;     // wall time of the last top-level build
};

// Builds both levels. Triangles with non-finite vertices are left out (ray
// queries treat them as inactive too). Throws std::runtime_error if Embree fails.
SceneBvh buildSceneBvh(const BvhInput& input);

// Where deformable mesh `mesh`'s own level lives in a SceneBvh: fixed by its first build, every rebuild
// fills the same root, node range and triangle slots.
struct MeshLevelSlots {
  uint32_t root = 0, firstTriangle = 0, triangleCount = 0, nodeCapacity = 0;
};
MeshLevelSlots meshLevelSlots(const SceneBvh& bvh, uint32_t mesh);

// A level built anew from `input.positions` (Embree), ready to copy into its slots: `slots.nodeCapacity`
// nodes from the root (children as global node indices), the triangles in slot order, its bounds. No nodes
// when the new tree needs more nodes than the slots hold or a triangle is not finite. Touches no SceneBvh,
// so it may run on a worker thread while the scene is used. Throws std::runtime_error if Embree fails.
struct MeshLevel {
  std::vector<gpu::GpuBvhNode> nodes;
  std::vector<gpu::GpuBvhTriangle> triangles;
  glm::vec3 lo{0.0f}, hi{0.0f};
};
MeshLevel buildMeshLevel(const BvhInput& input, uint32_t mesh, const MeshLevelSlots& slots);
void installMeshLevel(const MeshLevel& level, uint32_t mesh, SceneBvh& bvh);

// Bottom-level nodes and triangle slots wherever they are held, addressed by their global indices: the
// scene's arrays, or a MeshLevel not yet installed (its slots' range), which a worker thread may walk.
struct LevelArrays {
  std::span<const gpu::GpuBvhNode> nodes;
  uint32_t firstNode = 0;  // the global index of nodes[0]
  std::span<const gpu::GpuBvhTriangle> triangles;
  uint32_t firstTriangle = 0;  // the global slot of triangles[0]
  const gpu::GpuBvhNode& node(uint32_t ref) const { return nodes[ref - firstNode]; }
  const gpu::GpuBvhTriangle& triangle(uint32_t slot) const { return triangles[slot - firstTriangle]; }
};
LevelArrays levelArrays(const SceneBvh& bvh);
LevelArrays levelArrays(const MeshLevel& level, const MeshLevelSlots& slots);

// buildMeshLevel then installMeshLevel, in place from the current `input.positions` (the top level's refit
// follows on the device). False, and nothing changed, where buildMeshLevel gave no nodes.
bool rebuildMeshLevel(const BvhInput& input, uint32_t mesh, SceneBvh& bvh);

// The surface-area cost of mesh `mesh`'s own level with its boxes refit to `input.positions` (on the
// CPU; the tree as it is): Σ over inner nodes of their box's area + Σ over leaves of their box's area ×
// their triangles, over the root box's area (a box test and a triangle test cost about the same on
// lavapipe). A level just built has its lowest; refits that move triangles away from their neighbours in
// the tree raise it, and traversal slows with it (docs/RESULTS.md, "Refit against rebuild").
double meshLevelCost(const BvhInput& input, const SceneBvh& bvh, uint32_t mesh);

// meshLevelCost kept up to date a part at a time, for updates of large meshes: the level is split into
// the subtrees three levels below its root, each part's sum and box kept here; a call re-measures parts
// in turn until it has measured `maxTriangles` triangles (at least one part; every part on the first
// call after clear()) and returns the cost from the kept sums, each part as of its last measure.
struct LevelCostParts {
  std::vector<uint32_t> parts;    // the subtrees' references, in walk order
  std::vector<double> sums;       // each part's areas (leaves' × their triangles)
  std::vector<glm::vec3> lo, hi;  // each part's box
  uint32_t next = 0;              // the part the next call measures first
  void clear() { *this = LevelCostParts{}; }
};
double meshLevelCostInParts(const BvhInput& input, const SceneBvh& bvh, uint32_t mesh, uint32_t maxTriangles,
                            LevelCostParts& parts);
// The same for the level rooted at `root` in `level` (mesh `mesh`'s, not necessarily installed).
double meshLevelCostInParts(const BvhInput& input, const LevelArrays& level, uint32_t root, uint32_t mesh,
                            uint32_t maxTriangles, LevelCostParts& parts);

// Rebuilds the top level from the instances' current transforms. Throws
// std::runtime_error when a merged instance moved (it should have been movable).
void rebuildTopLevel(std::span<const BvhInstance> instances, SceneBvh& bvh);

// Upper bounds of the top level's array sizes, for buffers allocated once.
size_t maxTopNodes(size_t instanceCount);
size_t maxTopInstances(size_t instanceCount);

}  // namespace gi
