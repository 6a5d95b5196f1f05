// Morton (Z-order) sorting. Lavapipe builds acceleration structures without
// spatial sorting, so Z-ordered triangles and instances make its traversal
// 1.3–9× faster; GPU builders (and the compute BVH, built by Embree) are
// unaffected. The module sorts what gi::createScene is handed (each
// primitive's triangles; the TLAS's instances), so no engine has to. An engine
// that wants its own copy of the geometry in the module's triangle order (to
// compare triangle ids with a CPU tracer, say) applies mortonSortTriangles to
// each primitive: sorting is stable, so sorted input stays as it is.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace gi {

// 30-bit Morton code of p inside [lo, hi] (10 bits per axis, x the most significant).
uint32_t mortonCode(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi);

// The permutation that sorts `points` by Morton code within their bounds (stable).
std::vector<uint32_t> mortonOrder(std::span<const glm::vec3> points);

// Reorders the triangles of `indices` (a triangle list indexing `positions`)
// in Morton order of their centroids; every triangle stays whole.
void mortonSortTriangles(std::span<const glm::vec3> positions, std::span<uint32_t> indices);

}  // namespace gi
