#include "scene/prepared_level.h"

namespace gi {

PreparedLevel prepareMeshLevel(const BvhInput& input, uint32_t mesh, const MeshLevelSlots& slots) {
  PreparedLevel p;
  p.level = buildMeshLevel(input, mesh, slots);
  if (p.level.nodes.empty()) return p;
  const LevelArrays arrays = levelArrays(p.level, slots);
  p.cost = meshLevelCostInParts(input, arrays, slots.root, mesh, UINT32_MAX, p.costParts);
  p.refit = meshRefit(arrays, slots.root, p.order);
  return p;
}

}  // namespace gi
