// The foreign engine's own glTF loading (tinygltf): untextured triangle
// meshes with normals, metallic-roughness materials with emission, punctual
// lights and the first perspective camera. Anything else is refused with a
// message naming the file and what it holds.
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include <gi/scene.h>

namespace foreign {

struct Mesh {
  std::vector<glm::vec3> positions, normals;  // object space
  std::vector<uint32_t> indices;
  std::vector<gi::PrimitiveDesc> primitives;  // ranges of the arrays above
};

struct Instance {
  uint32_t mesh = 0;
  glm::mat4 worldFromObject{1.0f};
};

struct Camera {
  glm::mat4 worldFromView{1.0f};  // orthonormal: looks down −Z
  float yfov = 1.0f;              // radians
  float znear = 0.05f;            // metres
};

struct SceneFile {
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<gi::MaterialDesc> materials;  // the module's terms are glTF's
  std::vector<gi::LightDesc> lights;
  Camera camera;
};

bool loadScene(const std::string& path, SceneFile& out, std::string& error);

}  // namespace foreign
