// The Morton (Z-order) sorting gi/morton.h describes, on GLM vectors: the module's own uses (each
// primitive's triangles, the TLAS's instances) and the unit tests.
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

// Reorders the triangles of `indices` (a triangle list indexing `positions`) in Morton order of their
// centroids; every triangle stays whole.
void mortonSortTriangles(std::span<const glm::vec3> positions, std::span<uint32_t> indices);

}  // namespace gi
