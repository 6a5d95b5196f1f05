#include "scene.h"

#include <glm/gtc/matrix_transform.hpp>

namespace engine {

Bounds Scene::worldBounds() const {
  Bounds b;
  for (const Instance& inst : instances) {
    const Mesh& mesh = meshes[inst.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
      const Primitive& prim = primitives[p];
      for (uint32_t v = 0; v < prim.vertexCount; ++v)
        b.grow(glm::vec3(inst.worldFromObject * glm::vec4(positions[prim.vertexOffset + v], 1.0f)));
    }
  }
  return b;
}

size_t Scene::triangleCount() const {
  size_t n = 0;
  for (const Instance& inst : instances) {
    const Mesh& mesh = meshes[inst.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
      n += primitives[p].indexCount / 3;
  }
  return n;
}

bool Scene::hasEmissiveGeometry() const {
  for (const Instance& inst : instances) {
    const Mesh& mesh = meshes[inst.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
      if (materials[primitives[p].material].isEmissive()) return true;
  }
  return false;
}

Camera defaultCamera(const Bounds& bounds) {
  Camera cam;
  cam.name = "default";
  glm::vec3 center = bounds.empty() ? glm::vec3(0.0f) : bounds.center();
  float radius = bounds.empty() ? 1.0f : 0.5f * glm::length(bounds.max - bounds.min);
  radius = glm::max(radius, 1e-3f);
  // Distance at which the bounding sphere fits the vertical field of view.
  float distance = radius / std::sin(0.5f * cam.yfov);
  glm::vec3 eye = center + glm::vec3(0.0f, 0.25f * radius, distance);
  cam.worldFromView = glm::inverse(glm::lookAt(eye, center, glm::vec3(0.0f, 1.0f, 0.0f)));
  cam.znear = glm::max(1e-4f, 1e-3f * radius);
  return cam;
}

void generateNormals(Scene& scene, const Primitive& prim) {
  std::vector<glm::vec3> accum(prim.vertexCount, glm::vec3(0.0f));
  for (uint32_t i = 0; i + 2 < prim.indexCount; i += 3) {
    uint32_t a = scene.indices[prim.firstIndex + i], b = scene.indices[prim.firstIndex + i + 1],
             c = scene.indices[prim.firstIndex + i + 2];
    const glm::vec3& pa = scene.positions[prim.vertexOffset + a];
    // The cross product's length is twice the area: area weighting for free.
    glm::vec3 n = glm::cross(scene.positions[prim.vertexOffset + b] - pa, scene.positions[prim.vertexOffset + c] - pa);
    accum[a] += n;
    accum[b] += n;
    accum[c] += n;
  }
  for (uint32_t v = 0; v < prim.vertexCount; ++v) {
    float len = glm::length(accum[v]);
    scene.normals[prim.vertexOffset + v] = len > 0.0f ? accum[v] / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

}  // namespace engine
