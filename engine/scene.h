// The CPU scene model: only what rendering needs. Geometry is merged into one
// vertex/index pool; each glTF primitive is a `Primitive` (a BLAS geometry),
// each glTF mesh a `Mesh` (a BLAS), each node with a mesh an `Instance`.
// Units: metres; emission in W/(sr·m²); punctual intensity in W/sr (point,
// spot) or W/m² (directional), taken as-is from KHR_lights_punctual.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "gltf_animation.h"
#include "sky.h"

namespace engine {

enum class AlphaMode : uint32_t { Opaque, Mask, Blend };

struct Material {
  std::string name;
  glm::vec4 baseColor{1.0f};
  glm::vec3 emission{0.0f};  // emissiveFactor × KHR_materials_emissive_strength
  float metallic = 1.0f;     // glTF defaults
  float roughness = 1.0f;
  AlphaMode alphaMode = AlphaMode::Opaque;  // Blend is treated as opaque for lighting
  float alphaCutoff = 0.5f;
  int32_t baseColorTexture = -1;  // index into Scene::textures
  int32_t metallicRoughnessTexture = -1;
  int32_t emissiveTexture = -1;

  bool isEmissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

struct Texture {
  std::string name;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba8;  // tightly packed
  bool srgb = true;            // base colour and emissive are sRGB; metallic-roughness is linear
};

struct Primitive {
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
  uint32_t vertexOffset = 0;
  uint32_t vertexCount = 0;
  uint32_t material = 0;
};

struct Mesh {
  std::string name;
  uint32_t firstPrimitive = 0;
  uint32_t primitiveCount = 0;
  bool deformable = false;  // its vertices may change after upload (gi::MeshDesc::deformable; recordMeshVertexUpdate)
};

struct Instance {
  std::string name;
  uint32_t mesh = 0;
  glm::mat4 worldFromObject{1.0f};
  bool movable = false;  // its transform may change after upload (the compute BVH keeps it out of the static level)
};

enum class LightType : uint32_t { Point = 0, Spot = 1, Directional = 2 };

struct PunctualLight {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // the direction light travels (node -Z)
  glm::vec3 intensity{1.0f};               // colour × intensity
  float range = 0.0f;                      // 0 = infinite
  float innerConeAngle = 0.0f;             // radians
  float outerConeAngle = 0.7853982f;
};

struct Camera {
  std::string name;
  glm::mat4 worldFromView{1.0f};  // view looks down -Z, +Y up
  float yfov = 1.0472f;           // radians
  float znear = 0.05f;            // metres
  float zfar = 0.0f;              // 0 = infinite
};

struct Bounds {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  bool empty() const { return min.x > max.x; }
  glm::vec3 center() const { return 0.5f * (min + max); }
  float extent() const { return empty() ? 0.0f : glm::max(max.x - min.x, glm::max(max.y - min.y, max.z - min.z)); }
  void grow(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
};

struct Scene {
  std::string sourcePath;
  std::vector<glm::vec3> positions;  // object space
  std::vector<glm::vec3> normals;    // object space, unit length
  std::vector<glm::vec2> uvs;        // zero where the file has none
  std::vector<uint32_t> indices;     // relative to the primitive's vertexOffset
  std::vector<Primitive> primitives;
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<PunctualLight> lights;
  std::vector<Camera> cameras;     // never empty after loading: a default camera is added if needed
  Sky sky;                         // not in glTF: set by the caller (--sky); black by default
  uint32_t lightSampler = 2;       // not in glTF: --light-sampler, gi::SceneCreateDesc's (gpu::LIGHT_SAMPLER_TREE)
  uint32_t lightTreeCut = 4;       // not in glTF: --light-tree-cut, gi::SceneCreateDesc's
  bool bothTraversals = false;     // not in glTF: build both traversals' structures where the device has ray queries
                                   // (tests and benchmarks that compare them); else only the context's traversal
  float rebuildCostRatio = -1.0f;  // not in glTF: gi::SceneCreateDesc's (below 0: the module's default)
  bool rebuildOffThread = true;    // not in glTF: gi::SceneCreateDesc's
  SceneAnimations gltf;            // the file's node hierarchy, animations and skins (engine/gltf_animation.h)

  Bounds worldBounds() const;
  size_t triangleCount() const;  // instanced triangles
  bool hasEmissiveGeometry() const;
};

// A camera framing the whole scene from its +Z side, used when a file has none.
Camera defaultCamera(const Bounds& bounds);

// Smooth vertex normals from area-weighted face normals, for primitives without NORMAL.
void generateNormals(Scene& scene, const Primitive& primitive);

}  // namespace engine
