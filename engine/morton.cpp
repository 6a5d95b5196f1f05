#include "morton.h"

#include <algorithm>
#include <numeric>

namespace engine {
namespace {
// Spreads the low 10 bits of v so two zero bits follow each.
uint32_t spreadBits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}
}  // namespace

uint32_t mortonCode(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
  glm::vec3 size = glm::max(hi - lo, glm::vec3(1e-30f));
  glm::vec3 unit = glm::clamp((p - lo) / size, 0.0f, 1.0f);
  glm::uvec3 q = glm::uvec3(glm::min(unit * 1024.0f, glm::vec3(1023.0f)));
  return (spreadBits(q.x) << 2) | (spreadBits(q.y) << 1) | spreadBits(q.z);
}

std::vector<uint32_t> mortonOrder(std::span<const glm::vec3> points) {
  Bounds b;
  for (const glm::vec3& p : points) b.grow(p);
  std::vector<uint32_t> codes(points.size());
  for (size_t i = 0; i < points.size(); ++i) codes[i] = mortonCode(points[i], b.min, b.max);
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) { return codes[a] < codes[c]; });
  return order;
}

void mortonSortScene(Scene& scene) {
  for (const Primitive& prim : scene.primitives) {
    uint32_t triangles = prim.indexCount / 3;
    std::vector<glm::vec3> centroids(triangles);
    const uint32_t* idx = scene.indices.data() + prim.firstIndex;
    for (uint32_t t = 0; t < triangles; ++t)
      centroids[t] = (scene.positions[prim.vertexOffset + idx[3 * t]] + scene.positions[prim.vertexOffset + idx[3 * t + 1]] +
                      scene.positions[prim.vertexOffset + idx[3 * t + 2]]) / 3.0f;
    std::vector<uint32_t> order = mortonOrder(centroids);
    std::vector<uint32_t> sorted(prim.indexCount);
    for (uint32_t t = 0; t < triangles; ++t)
      for (int k = 0; k < 3; ++k) sorted[3 * t + k] = idx[3 * order[t] + k];
    std::copy(sorted.begin(), sorted.end(), scene.indices.begin() + prim.firstIndex);
  }
  std::vector<glm::vec3> centres(scene.instances.size());
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    // Sort by the centre of the instance's world bounds (many files leave node transforms at identity).
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    Bounds b;
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
      for (uint32_t v = 0; v < scene.primitives[p].vertexCount; ++v)
        b.grow(scene.positions[scene.primitives[p].vertexOffset + v]);
    centres[i] = glm::vec3(inst.worldFromObject * glm::vec4(b.empty() ? glm::vec3(0.0f) : b.center(), 1.0f));
  }
  std::vector<uint32_t> order = mortonOrder(centres);
  std::vector<Instance> sorted;
  sorted.reserve(order.size());
  for (uint32_t i : order) sorted.push_back(scene.instances[i]);
  scene.instances = std::move(sorted);
}

}  // namespace engine
