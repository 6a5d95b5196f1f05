#include "gltf_scene.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace foreign {
namespace {

struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The bytes of element i of an accessor.
const unsigned char* element(const tinygltf::Model& model, const tinygltf::Accessor& a, size_t i, size_t size) {
  if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
    throw Failure("an accessor has no buffer view");
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  const tinygltf::Buffer& buffer = model.buffers[size_t(view.buffer)];
  const size_t stride = view.byteStride ? view.byteStride : size;
  const size_t offset = view.byteOffset + a.byteOffset + stride * i;
  if (offset + size > buffer.data.size()) throw Failure("an accessor runs past its buffer");
  return buffer.data.data() + offset;
}

std::vector<glm::vec3> readVec3(const tinygltf::Model& model, int index, const char* what) {
  if (index < 0 || size_t(index) >= model.accessors.size()) throw Failure(std::string("no ") + what + " accessor");
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    throw Failure(std::string(what) + " is not float VEC3");
  std::vector<glm::vec3> out(a.count);
  for (size_t i = 0; i < a.count; ++i) std::memcpy(&out[i], element(model, a, i, 12), 12);
  return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, size_t vertexCount) {
  std::vector<uint32_t> out;
  if (index < 0) {  // not indexed: 0, 1, 2, ...
    for (uint32_t i = 0; i < vertexCount; ++i) out.push_back(i);
    return out;
  }
  const tinygltf::Accessor& a = model.accessors.at(size_t(index));
  for (size_t i = 0; i < a.count; ++i) {
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out.push_back(*element(model, a, i, 1)); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, element(model, a, i, 2), 2);
        out.push_back(v);
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, element(model, a, i, 4), 4);
        out.push_back(v);
        break;
      }
      default: throw Failure("indices are not unsigned integers");
    }
  }
  return out;
}

glm::mat4 localTransform(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = float(n.matrix[size_t(i)]);
    return m;
  }
  glm::mat4 t(1.0f), r(1.0f), s(1.0f);
  if (n.translation.size() == 3)
    t[3] = glm::vec4(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]), 1.0f);
  if (n.rotation.size() == 4)
    r = glm::mat4_cast(
        glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])));
  if (n.scale.size() == 3)
    s = glm::scale(glm::mat4(1.0f), glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
  return t * r * s;
}

gi::MaterialDesc material(const tinygltf::Material& m) {
  if (m.pbrMetallicRoughness.baseColorTexture.index >= 0 ||
      m.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0 || m.emissiveTexture.index >= 0)
    throw Failure("material '" + m.name + "' is textured, which this example does not handle");
  gi::MaterialDesc d;
  for (int k = 0; k < 4; ++k) d.baseColor[k] = float(m.pbrMetallicRoughness.baseColorFactor[size_t(k)]);
  d.metallic = float(m.pbrMetallicRoughness.metallicFactor);
  d.roughness = float(m.pbrMetallicRoughness.roughnessFactor);
  for (int k = 0; k < 3; ++k) d.emissive[k] = float(m.emissiveFactor[size_t(k)]);
  if (auto ext = m.extensions.find("KHR_materials_emissive_strength"); ext != m.extensions.end())
    d.emissiveStrength = float(ext->second.Get("emissiveStrength").GetNumberAsDouble());
  d.alphaMode = m.alphaMode == "MASK"    ? gi::AlphaMode::Mask
                : m.alphaMode == "BLEND" ? gi::AlphaMode::Blend
                                         : gi::AlphaMode::Opaque;
  d.alphaCutoff = float(m.alphaCutoff);
  return d;
}

struct Loader {
  const tinygltf::Model& model;
  SceneFile& out;
  bool haveCamera = false;
  uint32_t defaultMaterial = UINT32_MAX;

  uint32_t materialIndex(int m) {
    if (m >= 0) return uint32_t(m);
    if (defaultMaterial == UINT32_MAX) {  // glTF's default material
      defaultMaterial = uint32_t(out.materials.size());
      gi::MaterialDesc metal;
      metal.metallic = 1.0f;  // glTF's default material: its metallicFactor is 1
      out.materials.push_back(metal);
    }
    return defaultMaterial;
  }

  uint32_t loadMesh(const tinygltf::Mesh& gm) {
    Mesh mesh;
    for (const tinygltf::Primitive& p : gm.primitives) {
      if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1)
        throw Failure("mesh '" + gm.name + "' has non-triangle primitives");
      auto position = p.attributes.find("POSITION"), normal = p.attributes.find("NORMAL");
      if (position == p.attributes.end() || normal == p.attributes.end())
        throw Failure("mesh '" + gm.name + "' has a primitive without POSITION and NORMAL");
      std::vector<glm::vec3> positions = readVec3(model, position->second, "POSITION");
      std::vector<glm::vec3> normals = readVec3(model, normal->second, "NORMAL");
      std::vector<uint32_t> indices = readIndices(model, p.indices, positions.size());
      if (normals.size() != positions.size())
        throw Failure("mesh '" + gm.name + "': NORMAL and POSITION differ in count");
      gi::PrimitiveDesc prim;
      prim.firstIndex = uint32_t(mesh.indices.size());
      prim.indexCount = uint32_t(indices.size());
      prim.firstVertex = uint32_t(mesh.positions.size());
      prim.vertexCount = uint32_t(positions.size());
      prim.material = materialIndex(p.material);
      mesh.primitives.push_back(prim);
      mesh.positions.insert(mesh.positions.end(), positions.begin(), positions.end());
      mesh.normals.insert(mesh.normals.end(), normals.begin(), normals.end());
      mesh.indices.insert(mesh.indices.end(), indices.begin(), indices.end());
    }
    out.meshes.push_back(std::move(mesh));
    return uint32_t(out.meshes.size() - 1);
  }

  void visit(int index, const glm::mat4& parent, std::vector<int>& meshIndex) {
    const tinygltf::Node& n = model.nodes.at(size_t(index));
    const glm::mat4 world = parent * localTransform(n);
    if (n.mesh >= 0) {
      int& m = meshIndex.at(size_t(n.mesh));
      if (m < 0) m = int(loadMesh(model.meshes.at(size_t(n.mesh))));
      out.instances.push_back({uint32_t(m), world});
    }
    if (n.camera >= 0 && !haveCamera && model.cameras.at(size_t(n.camera)).type == "perspective") {
      const tinygltf::PerspectiveCamera& p = model.cameras[size_t(n.camera)].perspective;
      glm::vec3 x = glm::normalize(glm::vec3(world[0])),
                z = glm::normalize(glm::cross(glm::vec3(world[0]), glm::vec3(world[1])));
      glm::vec3 y = glm::cross(z, x);
      out.camera = {glm::mat4(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f), world[3]), float(p.yfov),
                    float(p.znear)};
      haveCamera = true;
    }
    if (auto ext = n.extensions.find("KHR_lights_punctual"); ext != n.extensions.end()) {
      const tinygltf::Light& l = model.lights.at(size_t(ext->second.Get("light").GetNumberAsInt()));
      gi::LightDesc d;
      d.type = l.type == "spot"          ? gi::LightType::Spot
               : l.type == "directional" ? gi::LightType::Directional
                                         : gi::LightType::Point;
      const glm::vec3 position(world[3]), direction = glm::normalize(-glm::vec3(world[2]));
      for (int k = 0; k < 3; ++k) {
        d.position[k] = position[k];
        d.direction[k] = direction[k];
        d.intensity[k] = float((l.color.size() == 3 ? l.color[size_t(k)] : 1.0) * l.intensity);
      }
      d.range = float(l.range);
      d.innerConeAngle = float(l.spot.innerConeAngle);
      d.outerConeAngle = float(l.spot.outerConeAngle);
      out.lights.push_back(d);
    }
    for (int child : n.children) visit(child, world, meshIndex);
  }
};

}  // namespace

bool loadScene(const std::string& path, SceneFile& out, std::string& error) {
  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  std::string warning;
  if (!gltf.LoadASCIIFromFile(&model, &error, &warning, path)) {
    error = path + ": " + error;
    return false;
  }
  try {
    out = SceneFile{};
    for (const tinygltf::Material& m : model.materials) out.materials.push_back(material(m));
    Loader loader{model, out};
    std::vector<int> meshIndex(model.meshes.size(), -1);
    const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (model.scenes.empty()) throw Failure("no scene");
    for (int root : model.scenes.at(size_t(sceneIndex)).nodes) loader.visit(root, glm::mat4(1.0f), meshIndex);
    if (!loader.haveCamera) throw Failure("no perspective camera");
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace foreign
