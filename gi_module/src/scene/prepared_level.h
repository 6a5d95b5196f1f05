// A deformable mesh's level rebuilt and made ready to install, on whichever thread built it: Embree's tree
// in its slots, its cost walked once in the pose it was built from, its refit order derived. What is left
// for the update that installs it is copying it in and writing it to the device.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/bvh_builder.h"
#include "scene/refit.h"

namespace gi {

struct PreparedLevel {
  MeshLevel level;           // no nodes: the build found no room or a triangle not finite
  double cost = 0.0;         // its cost in the pose it was built from: what its refits are weighed against
  LevelCostParts costParts;  // primed by the walk that gave the cost
  MeshRefit refit;           // its refit levels, indexing `order` from 0
  std::vector<uint32_t> order;
};

// Builds mesh `mesh`'s level from input.positions into `slots` and prepares it. Touches no SceneBvh, so it
// may run on a worker thread while the scene is used. Throws std::runtime_error if Embree fails.
PreparedLevel prepareMeshLevel(const BvhInput& input, uint32_t mesh, const MeshLevelSlots& slots);

}  // namespace gi
