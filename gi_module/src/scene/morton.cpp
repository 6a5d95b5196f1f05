#include "gi/morton.h"
#include "scene/morton_order.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace gi {
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
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  std::vector<uint32_t> codes(points.size());
  for (size_t i = 0; i < points.size(); ++i) codes[i] = mortonCode(points[i], lo, hi);
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) { return codes[a] < codes[c]; });
  return order;
}

void mortonSortTriangles(std::span<const glm::vec3> positions, std::span<uint32_t> indices) {
  const size_t triangles = indices.size() / 3;
  std::vector<glm::vec3> centroids(triangles);
  for (size_t t = 0; t < triangles; ++t)
    centroids[t] = (positions[indices[3 * t]] + positions[indices[3 * t + 1]] + positions[indices[3 * t + 2]]) / 3.0f;
  std::vector<uint32_t> order = mortonOrder(centroids);
  std::vector<uint32_t> sorted(triangles * 3);
  for (size_t t = 0; t < triangles; ++t)
    for (size_t k = 0; k < 3; ++k) sorted[3 * t + k] = indices[3 * order[t] + k];
  std::copy(sorted.begin(), sorted.end(), indices.begin());
}

void mortonSortTriangles(std::span<const float> positionsXyz, std::span<uint32_t> indices) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "glm::vec3 is three packed floats");
  mortonSortTriangles(std::span(reinterpret_cast<const glm::vec3*>(positionsXyz.data()), positionsXyz.size() / 3),
                      indices);
}

}  // namespace gi
