#include "deformed_grid.h"

#include <algorithm>
#include <cmath>

namespace tools {

uint32_t appendGrid(engine::Scene& scene, uint32_t side, glm::vec3 centre, float width) {
  engine::Primitive primitive;
  primitive.firstIndex = uint32_t(scene.indices.size());
  primitive.vertexOffset = uint32_t(scene.positions.size());
  primitive.vertexCount = (side + 1) * (side + 1);
  for (uint32_t z = 0; z <= side; ++z)
    for (uint32_t x = 0; x <= side; ++x) {
      scene.positions.push_back(centre +
                                width * glm::vec3(float(x) / float(side) - 0.5f, 0.0f, float(z) / float(side) - 0.5f));
      scene.normals.push_back({0.0f, 1.0f, 0.0f});
      scene.uvs.push_back({0.0f, 0.0f});
    }
  for (uint32_t z = 0; z < side; ++z)
    for (uint32_t x = 0; x < side; ++x) {
      const uint32_t a = z * (side + 1) + x, b = a + 1, c = a + side + 1, d = c + 1;
      scene.indices.insert(scene.indices.end(), {a, c, b, b, c, d});
    }
  primitive.indexCount = uint32_t(scene.indices.size()) - primitive.firstIndex;
  engine::Mesh mesh;
  mesh.firstPrimitive = uint32_t(scene.primitives.size());
  mesh.primitiveCount = 1;
  mesh.deformable = true;
  scene.primitives.push_back(primitive);
  scene.meshes.push_back(mesh);
  engine::Instance instance;
  instance.mesh = uint32_t(scene.meshes.size() - 1);
  scene.instances.push_back(instance);
  return instance.mesh;
}

void foldGrid(engine::Scene& scene, uint32_t mesh, const std::vector<glm::vec3>& rest, uint32_t folds, float amount,
              float ripple) {
  const engine::Primitive& p = scene.primitives[scene.meshes[mesh].firstPrimitive];
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (uint32_t v = p.vertexOffset; v < p.vertexOffset + p.vertexCount; ++v) {
    lo = glm::min(lo, rest[v]);
    hi = glm::max(hi, rest[v]);
  }
  for (uint32_t v = p.vertexOffset; v < p.vertexOffset + p.vertexCount; ++v) {
    const float u = (rest[v].x - lo.x) / (hi.x - lo.x) * float(folds);
    const float strip = std::min(std::floor(u), float(folds - 1)), along = u - strip;
    const float folded = (int(strip) % 2 ? 1.0f - along : along) / float(folds);
    glm::vec3 q = rest[v];
    q.x = lo.x + (hi.x - lo.x) * glm::mix(u / float(folds), folded, amount);
    q.y += amount * 0.001f * strip + ripple * std::sin(40.0f * rest[v].z);
    scene.positions[v] = q;
  }
}

}  // namespace tools
