// gi-bench --refit: what a deforming mesh costs a frame. A grid of each
// triangle count, created deformable, is twisted and handed over
// (gi::updateMeshVertices: the vertices' copy, the compute BVH's refit and,
// with ray queries, the BLAS update and TLAS rebuild), against creating its
// scene anew in that pose (gi::createScene: Embree's build of the BVH and,
// with ray queries, the BLAS and TLAS builds; the mesh then not deformable).
// Each traversal backend the
// device has: a compute scene, and a ray-query scene (which holds the compute
// BVH too, and refits both).
#pragma once
#include <filesystem>
#include <span>
#include <string>

#include "context.h"

namespace tools {

// Prints a table, appends rows to DIR/refit.csv (header written when the file is new). Returns false with
// `error` set if a file cannot be written.
bool benchRefit(const engine::Context& ctx, std::span<const uint32_t> triangleCounts, const std::filesystem::path& dir,
                std::string& error);

// What refits cost tracing as a deformation grows: a grid of 20,000 triangles folded step by step
// (tools/deformed_grid.h), refit (gi::SceneCreateDesc::rebuildCostRatio 0) against the same pose built
// anew: the level's surface-area cost ratio (gi::SceneInfo::refitCostRatio) and each backend's primary
// and diffuse Mrays/s, both scenes. Prints a table, appends to DIR/refit_quality.csv.
bool benchRefitQuality(const engine::Context& ctx, const std::filesystem::path& dir, std::string& error);

// What the update that finds a level degraded costs (gi::SceneCreateDesc::rebuildCostRatio 1.5): a grid of
// each triangle count folded flat at once, compute traversal, CPU ms of the update that rebuilds it
// (rebuildOffThread false) against a refit, the update that starts the rebuild off thread and the update
// that installs it (the same pose handed over every 5 ms until then). Prints a table, appends to
// DIR/refit_rebuild.csv.
bool benchRefitRebuild(const engine::Context& ctx, std::span<const uint32_t> triangleCounts,
                       const std::filesystem::path& dir, std::string& error);

}  // namespace tools
