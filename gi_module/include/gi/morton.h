// Morton (Z-order) sorting. Lavapipe builds acceleration structures without
// spatial sorting, so Z-ordered triangles and instances make its traversal
// 1.3–9× faster; GPU builders (and the compute BVH, built by Embree) are
// unaffected. The module sorts what gi::createScene is handed (each
// primitive's triangles; the TLAS's instances), so no engine has to. An engine
// that wants its own copy of the geometry in the module's triangle order (to
// compare triangle ids with a CPU tracer, say) applies mortonSortTriangles to
// each primitive: sorting is stable, so sorted input stays as it is.
#pragma once
#include <cstdint>
#include <span>

namespace gi {

// Reorders the triangles of `indices` (a triangle list indexing `positionsXyz`, three floats a vertex) in
// Morton order of their centroids, as gi::createScene orders each primitive's; every triangle stays whole.
void mortonSortTriangles(std::span<const float> positionsXyz, std::span<uint32_t> indices);

}  // namespace gi
