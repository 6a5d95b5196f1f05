// A deformable grid for the refit tests and benchmarks: appended to an engine scene, and folded like an
// accordion, the deformation that degrades a refit BVH most (neighbours in the rest pose's tree end up
// far apart, far ones on top of each other).
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "scene.h"

namespace tools {

// A deformable square grid of side × side quads (2 side² triangles) appended to `scene` (its own mesh and
// instance, material 0), `width` metres wide at `centre`, facing up; returns its mesh.
uint32_t appendGrid(engine::Scene& scene, uint32_t side, glm::vec3 centre, float width);

// The grid of `mesh` folded along x into `folds` strips from its rest positions `rest` (amount 0: flat,
// 1: folded flat, the strips stacked 1 mm apart), rippled by `ripple` metres.
void foldGrid(engine::Scene& scene, uint32_t mesh, const std::vector<glm::vec3>& rest, uint32_t folds, float amount,
              float ripple);

}  // namespace tools
