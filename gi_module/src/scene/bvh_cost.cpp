// The surface-area cost of a deformable mesh's level as refit to its current vertices (bvh_builder.h's
// meshLevelCost): what gi::updateMeshVertices weighs to decide between refitting and rebuilding.
#include <cmath>

#include "bvh_builder.h"

namespace gi {
namespace {

struct Box {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  double area() const {
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return 0.0;
    const glm::dvec3 d = glm::dvec3(hi) - glm::dvec3(lo);
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
};

// The level's boxes refit bottom up to the current positions, their weighted areas summed on the way.
struct CostWalk {
  const BvhInput& input;
  const LevelArrays& level;
  const BvhMesh& mesh;
  double sum = 0.0;
  uint32_t triangles = 0;  // measured so far

  Box triangle(uint32_t slot) const {
    const gpu::GpuBvhTriangle& t = level.triangle(slot);
    Box b;
    for (const BvhGeometry& g : mesh.geometries) {
      if (g.id != t.geometry) continue;
      for (uint32_t k = 0; k < 3; ++k)
        b.grow(input.positions[input.indices[g.firstIndex + 3 * t.triangle + k] + g.vertexOffset]);
    }
    return b;
  }

  Box walk(uint32_t ref) {
    Box box;
    if (ref & gpu::BVH_LEAF_BIT) {
      const uint32_t first = ref & gpu::BVH_LEAF_FIRST_MASK, count = ((ref >> gpu::BVH_LEAF_COUNT_SHIFT) & 0xfu) + 1u;
      for (uint32_t i = 0; i < count; ++i) box.grow(triangle(first + i));
      sum += box.area() * count;
      triangles += count;
      return box;
    }
    const gpu::GpuBvhNode& n = level.node(ref);
    for (int k = 0; k < int(gpu::BVH_WIDTH); ++k)
      if (n.child[k] != gpu::BVH_NO_CHILD) box.grow(walk(n.child[k]));
    sum += box.area();
    return box;
  }
};

constexpr int kPartDepth = 3;  // the parts: the subtrees this many levels below the root (at most 64)

bool isPart(uint32_t ref, int depth) { return depth == kPartDepth || (ref & gpu::BVH_LEAF_BIT); }

void collectParts(const LevelArrays& level, uint32_t ref, int depth, std::vector<uint32_t>& parts) {
  if (isPart(ref, depth)) {
    parts.push_back(ref);
    return;
  }
  const gpu::GpuBvhNode& n = level.node(ref);
  for (uint32_t child : {n.child.x, n.child.y, n.child.z, n.child.w})
    if (child != gpu::BVH_NO_CHILD) collectParts(level, child, depth + 1, parts);
}

// The nodes above the parts: their boxes from the parts' kept boxes, their areas and the parts' sums added
// to `sum` (the parts visited in walk order, `part` counting them).
Box topBox(const LevelArrays& level, uint32_t ref, int depth, const LevelCostParts& p, size_t& part, double& sum) {
  if (isPart(ref, depth)) {
    sum += p.sums[part];
    Box b;
    b.lo = p.lo[part];
    b.hi = p.hi[part];
    ++part;
    return b;
  }
  Box box;
  const gpu::GpuBvhNode& n = level.node(ref);
  for (uint32_t child : {n.child.x, n.child.y, n.child.z, n.child.w})
    if (child != gpu::BVH_NO_CHILD) box.grow(topBox(level, child, depth + 1, p, part, sum));
  sum += box.area();
  return box;
}

}  // namespace

double meshLevelCostInParts(const BvhInput& input, const SceneBvh& bvh, uint32_t mesh, uint32_t maxTriangles,
                            LevelCostParts& p) {
  if (mesh >= bvh.meshRoot.size() || bvh.meshRoot[mesh] == gpu::BVH_NO_CHILD) return 0.0;
  return meshLevelCostInParts(input, levelArrays(bvh), bvh.meshRoot[mesh], mesh, maxTriangles, p);
}

double meshLevelCostInParts(const BvhInput& input, const LevelArrays& level, uint32_t root, uint32_t mesh,
                            uint32_t maxTriangles, LevelCostParts& p) {
  const bool first = p.parts.empty();
  if (first) {
    collectParts(level, root, 0, p.parts);
    p.sums.assign(p.parts.size(), 0.0);
    p.lo.assign(p.parts.size(), glm::vec3(INFINITY));
    p.hi.assign(p.parts.size(), glm::vec3(-INFINITY));
  }
  CostWalk walk{input, level, input.meshes[mesh]};
  for (size_t measured = 0; measured < p.parts.size() && (first || measured == 0 || walk.triangles < maxTriangles);
       ++measured) {
    const uint32_t part = p.next;
    p.next = (p.next + 1) % uint32_t(p.parts.size());
    walk.sum = 0.0;
    const Box box = walk.walk(p.parts[part]);
    p.sums[part] = walk.sum;
    p.lo[part] = box.lo;
    p.hi[part] = box.hi;
  }
  double sum = 0.0;
  size_t part = 0;
  const double rootArea = topBox(level, root, 0, p, part, sum).area();
  return rootArea > 0.0 ? sum / rootArea : 0.0;
}

double meshLevelCost(const BvhInput& input, const SceneBvh& bvh, uint32_t mesh) {
  if (mesh >= bvh.meshRoot.size() || bvh.meshRoot[mesh] == gpu::BVH_NO_CHILD) return 0.0;
  const LevelArrays level = levelArrays(bvh);
  CostWalk walk{input, level, input.meshes[mesh]};
  const double rootArea = walk.walk(bvh.meshRoot[mesh]).area();
  return rootArea > 0.0 ? walk.sum / rootArea : 0.0;
}

}  // namespace gi
