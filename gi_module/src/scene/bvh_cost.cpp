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
  const SceneBvh& bvh;
  const BvhMesh& mesh;
  double sum = 0.0;

  Box triangle(uint32_t slot) const {
    const gpu::GpuBvhTriangle& t = bvh.triangles[slot];
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
      return box;
    }
    const gpu::GpuBvhNode& n = bvh.bottomNodes[ref];
    for (int k = 0; k < int(gpu::BVH_WIDTH); ++k)
      if (n.child[k] != gpu::BVH_NO_CHILD) box.grow(walk(n.child[k]));
    sum += box.area();
    return box;
  }
};

}  // namespace

double meshLevelCost(const BvhInput& input, const SceneBvh& bvh, uint32_t mesh) {
  if (mesh >= bvh.meshRoot.size() || bvh.meshRoot[mesh] == gpu::BVH_NO_CHILD) return 0.0;
  CostWalk walk{input, bvh, input.meshes[mesh]};
  const double rootArea = walk.walk(bvh.meshRoot[mesh]).area();
  return rootArea > 0.0 ? walk.sum / rootArea : 0.0;
}

}  // namespace gi
