#include "gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace engine {
namespace {

const char* const kSupportedExtensions[] = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};

// Thrown internally and turned into the error string at the API boundary.
struct LoadError {
  std::string message;
};

[[noreturn]] void fail(const std::string& message) { throw LoadError{message}; }

// A typed, bounds-checked view of one accessor's elements.
struct AccessorView {
  const uint8_t* data = nullptr;
  size_t count = 0;
  size_t stride = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;
};

size_t componentSize(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT4: return 16;  // inverse bind matrices
    default: return 0;
  }
}

AccessorView viewAccessor(const tinygltf::Model& model, int index, const std::string& what) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    fail(what + " refers to accessor " + std::to_string(index) + ", which does not exist");
  const tinygltf::Accessor& acc = model.accessors[index];
  std::string name = what + " (accessor " + std::to_string(index) + ")";
  if (acc.sparse.isSparse) fail(name + " is sparse, which is not supported");
  if (acc.bufferView < 0 || size_t(acc.bufferView) >= model.bufferViews.size()) fail(name + " has no valid bufferView");
  const tinygltf::BufferView& bv = model.bufferViews[acc.bufferView];
  if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
    fail(name + " uses a bufferView with no valid buffer");
  const tinygltf::Buffer& buf = model.buffers[bv.buffer];
  size_t csize = componentSize(acc.componentType);
  int comps = componentCount(acc.type);
  if (csize == 0 || comps == 0) fail(name + " has an unsupported component type or element type");
  size_t elementSize = csize * size_t(comps);
  size_t stride = bv.byteStride ? bv.byteStride : elementSize;
  if (stride < elementSize) fail(name + " has a byteStride smaller than its element");
  if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
    fail(name + " uses a bufferView that runs past the end of its buffer (" + std::to_string(buf.data.size()) +
         " bytes)");
  if (acc.count == 0) fail(name + " has no elements");
  size_t needed = acc.byteOffset + stride * (acc.count - 1) + elementSize;
  if (acc.byteOffset > bv.byteLength || needed > bv.byteLength || acc.count > (SIZE_MAX / stride))
    fail(name + " reads past the end of its bufferView (" + std::to_string(needed) + " > " +
         std::to_string(bv.byteLength) + " bytes)");
  AccessorView v;
  v.data = buf.data.data() + bv.byteOffset + acc.byteOffset;
  v.count = acc.count;
  v.stride = stride;
  v.componentType = acc.componentType;
  v.components = comps;
  v.normalized = acc.normalized;
  return v;
}

float readComponent(const AccessorView& v, size_t element, int component) {
  const uint8_t* p = v.data + element * v.stride + component * componentSize(v.componentType);
  switch (v.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return v.normalized ? *p / 255.0f : float(*p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t s;
      std::memcpy(&s, p, 2);
      return v.normalized ? s / 65535.0f : float(s);
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t b;
      std::memcpy(&b, p, 1);
      return v.normalized ? std::max(b / 127.0f, -1.0f) : float(b);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t s;
      std::memcpy(&s, p, 2);
      return v.normalized ? std::max(s / 32767.0f, -1.0f) : float(s);
    }
    default: return 0.0f;
  }
}

uint32_t readIndex(const AccessorView& v, size_t element) {
  const uint8_t* p = v.data + element * v.stride;
  switch (v.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t s;
      std::memcpy(&s, p, 2);
      return s;
    }
    default: {
      uint32_t i;
      std::memcpy(&i, p, 4);
      return i;
    }
  }
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double numberOr(const std::vector<double>& values, size_t i, double fallback) {
  return i < values.size() ? values[i] : fallback;
}

int textureImage(const tinygltf::Model& model, int textureIndex, const std::string& what) {
  if (textureIndex < 0) return -1;
  if (size_t(textureIndex) >= model.textures.size())
    fail(what + " refers to texture " + std::to_string(textureIndex) + ", which does not exist");
  int source = model.textures[textureIndex].source;
  if (source < 0 || size_t(source) >= model.images.size())
    fail(what + " uses texture " + std::to_string(textureIndex) + ", which has no valid image");
  return source;
}

struct Loader {
  const tinygltf::Model& model;
  Scene& scene;
  std::vector<int> meshMap;                  // glTF mesh -> scene mesh (-1 = not yet loaded)
  std::vector<std::array<int, 2>> imageMap;  // glTF image -> scene texture, per colour space (linear, sRGB)
  bool warnedMorphTargets = false, warnedExtraInfluences = false;  // each unsupported feature is named once

  // Skins: joints and inverse bind matrices (identity when the file gives none).
  void skins() {
    for (size_t k = 0; k < model.skins.size(); ++k) {
      const tinygltf::Skin& in = model.skins[k];
      const std::string what = "skin " + std::to_string(k) + " ('" + in.name + "')";
      Skin out;
      for (int j : in.joints) {
        if (j < 0 || size_t(j) >= model.nodes.size())
          fail(what + " has joint node " + std::to_string(j) + ", which does not exist");
        out.joints.push_back(j);
      }
      out.inverseBind.assign(out.joints.size(), glm::mat4(1.0f));
      if (in.inverseBindMatrices >= 0) {
        AccessorView m = viewAccessor(model, in.inverseBindMatrices, what + " inverseBindMatrices");
        if (m.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
            model.accessors[size_t(in.inverseBindMatrices)].type != TINYGLTF_TYPE_MAT4 || m.count < out.joints.size())
          fail(what + " inverseBindMatrices must be one MAT4 of FLOAT per joint");
        for (size_t j = 0; j < out.joints.size(); ++j)
          for (int c = 0; c < 16; ++c) {
            float f;
            std::memcpy(&f, m.data + j * m.stride + size_t(c) * 4, 4);
            if (!std::isfinite(f)) fail(what + " inverse bind matrix " + std::to_string(j) + " is not finite");
            glm::value_ptr(out.inverseBind[j])[c] = f;
          }
      }
      scene.gltf.skins.push_back(std::move(out));
    }
    for (const SkinnedMesh& sm : scene.gltf.skinnedMeshes) {
      const Mesh& mesh = scene.meshes[sm.mesh];
      for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
        for (uint32_t v = scene.primitives[p].vertexOffset;
             v < scene.primitives[p].vertexOffset + scene.primitives[p].vertexCount; ++v) {
          if (scene.gltf.vertexWeights[v] == glm::vec4(0.0f))
            fail("mesh '" + mesh.name + "' is skinned but its primitive " + std::to_string(p - mesh.firstPrimitive) +
                 " has no JOINTS_0/WEIGHTS_0");
          for (int k = 0; k < 4; ++k)
            if (scene.gltf.vertexJoints[v][k] >= scene.gltf.skins[sm.skin].joints.size())
              fail("mesh '" + mesh.name + "' vertex " + std::to_string(v - scene.primitives[p].vertexOffset) +
                   " names joint " + std::to_string(scene.gltf.vertexJoints[v][k]) + " of a skin with " +
                   std::to_string(scene.gltf.skins[sm.skin].joints.size()));
        }
    }
  }

  // Animations: translation, rotation and scale channels; morph weights and animated cameras are named.
  void animations() {
    for (size_t k = 0; k < model.animations.size(); ++k) {
      const tinygltf::Animation& in = model.animations[k];
      const std::string what = "animation " + std::to_string(k) + " ('" + in.name + "')";
      Animation out;
      out.name = in.name;
      for (size_t i = 0; i < in.samplers.size(); ++i) {
        const tinygltf::AnimationSampler& s = in.samplers[i];
        const std::string where = what + " sampler " + std::to_string(i);
        AnimationSampler sampler;
        if (s.interpolation == "STEP")
          sampler.interpolation = AnimationSampler::Interpolation::Step;
        else if (s.interpolation == "CUBICSPLINE")
          sampler.interpolation = AnimationSampler::Interpolation::CubicSpline;
        else if (s.interpolation.empty() || s.interpolation == "LINEAR")
          sampler.interpolation = AnimationSampler::Interpolation::Linear;
        else
          fail(where + " has interpolation '" + s.interpolation + "' (LINEAR, STEP or CUBICSPLINE)");
        AccessorView times = viewAccessor(model, s.input, where + " input");
        AccessorView values = viewAccessor(model, s.output, where + " output");
        if (times.components != 1 || times.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
          fail(where + " input must be SCALAR FLOAT");
        for (size_t t = 0; t < times.count; ++t) {
          const float time = readComponent(times, t, 0);
          if (!std::isfinite(time) || time < 0.0f || (t > 0 && time < sampler.times.back()))
            fail(where + " input time " + std::to_string(t) + " is not finite, negative or decreasing");
          sampler.times.push_back(time);
        }
        const size_t perKey = sampler.interpolation == AnimationSampler::Interpolation::CubicSpline ? 3 : 1;
        if (values.count < perKey * times.count) fail(where + " output has fewer values than its input has keys");
        for (size_t v = 0; v < perKey * times.count; ++v) {
          glm::vec4 value(0.0f);
          for (int c = 0; c < std::min(values.components, 4); ++c) value[c] = readComponent(values, v, c);
          if (!std::isfinite(value.x + value.y + value.z + value.w))
            fail(where + " output value " + std::to_string(v) + " is not finite");
          sampler.values.push_back(value);
        }
        out.seconds = std::max(out.seconds, sampler.times.back());
        out.samplers.push_back(std::move(sampler));
      }
      for (size_t c = 0; c < in.channels.size(); ++c) {
        const tinygltf::AnimationChannel& ch = in.channels[c];
        const std::string where = what + " channel " + std::to_string(c);
        if (ch.sampler < 0 || size_t(ch.sampler) >= out.samplers.size())
          fail(where + " refers to a sampler that does not exist");
        if (ch.target_node < 0) continue;  // no target: glTF says ignore it
        if (size_t(ch.target_node) >= model.nodes.size())
          fail(where + " targets node " + std::to_string(ch.target_node) + ", which does not exist");
        AnimationChannel channel;
        channel.node = ch.target_node;
        channel.sampler = ch.sampler;
        if (ch.target_path == "translation")
          channel.path = AnimationChannel::Path::Translation;
        else if (ch.target_path == "rotation")
          channel.path = AnimationChannel::Path::Rotation;
        else if (ch.target_path == "scale")
          channel.path = AnimationChannel::Path::Scale;
        else {
          std::fprintf(stderr, "%s: warning: %s animates '%s' (morph target weights), which is not played\n",
                       scene.sourcePath.c_str(), where.c_str(), ch.target_path.c_str());
          continue;
        }
        if (model.nodes[size_t(ch.target_node)].camera >= 0)
          std::fprintf(stderr, "%s: warning: %s moves a camera node; cameras are not animated (the view stays)\n",
                       scene.sourcePath.c_str(), where.c_str());
        if (scene.gltf.nodes[size_t(ch.target_node)].hasMatrix)
          fail(where + " animates node " + std::to_string(ch.target_node) + ", which has a matrix (glTF forbids both)");
        out.channels.push_back(channel);
      }
      scene.gltf.animations.push_back(std::move(out));
    }
  }

  int texture(int gltfTexture, bool srgb, const std::string& what) {
    int image = textureImage(model, gltfTexture, what);
    if (image < 0) return -1;
    int& slot = imageMap[image][srgb ? 1 : 0];
    if (slot >= 0) return slot;
    const tinygltf::Image& img = model.images[image];
    if (img.image.empty() || img.width <= 0 || img.height <= 0)
      fail("image " + std::to_string(image) + " ('" + img.uri + "') could not be decoded");
    if (img.bits != 8 && img.bits != 16) fail("image " + std::to_string(image) + " has unsupported bit depth");
    if (img.component < 1 || img.component > 4)
      fail("image " + std::to_string(image) + " has an unsupported channel count");
    size_t expected = size_t(img.width) * img.height * img.component * (img.bits / 8);
    if (img.image.size() < expected) fail("image " + std::to_string(image) + " holds fewer texels than its size says");
    Texture tex;
    tex.name = img.uri.empty() ? img.name : img.uri;
    tex.width = uint32_t(img.width);
    tex.height = uint32_t(img.height);
    tex.srgb = srgb;
    tex.rgba8.resize(size_t(tex.width) * tex.height * 4);
    for (size_t t = 0; t < size_t(tex.width) * tex.height; ++t) {
      uint8_t c[4] = {0, 0, 0, 255};
      for (int k = 0; k < img.component; ++k) {
        size_t at = (t * img.component + k) * (img.bits / 8);
        c[k] = img.bits == 8 ? img.image[at] : img.image[at + 1];  // 16-bit PNG texels are big-endian
      }
      if (img.component == 1) c[1] = c[2] = c[0];
      if (img.component == 2) {  // grey + alpha
        c[3] = c[1];
        c[1] = c[2] = c[0];
      }
      std::memcpy(&tex.rgba8[t * 4], c, 4);
    }
    slot = int(scene.textures.size());
    scene.textures.push_back(std::move(tex));
    return slot;
  }

  void materials() {
    for (size_t i = 0; i < model.materials.size(); ++i) {
      const tinygltf::Material& m = model.materials[i];
      std::string what = "material " + std::to_string(i) + " ('" + m.name + "')";
      Material out;
      out.name = m.name;
      const auto& pbr = m.pbrMetallicRoughness;
      for (int k = 0; k < 4; ++k) out.baseColor[k] = float(numberOr(pbr.baseColorFactor, k, 1.0));
      out.metallic = float(pbr.metallicFactor);
      out.roughness = float(pbr.roughnessFactor);
      float strength = 1.0f;
      auto ext = m.extensions.find("KHR_materials_emissive_strength");
      if (ext != m.extensions.end() && ext->second.Has("emissiveStrength"))
        strength = float(ext->second.Get("emissiveStrength").GetNumberAsDouble());
      for (int k = 0; k < 3; ++k) out.emission[k] = float(numberOr(m.emissiveFactor, k, 0.0)) * strength;
      if (!finite(glm::vec3(out.baseColor)) || !std::isfinite(out.baseColor.a) || !finite(out.emission) ||
          !std::isfinite(out.metallic) || !std::isfinite(out.roughness))
        fail(what + " has a non-finite factor");
      if (glm::any(glm::lessThan(out.emission, glm::vec3(0.0f))) || strength < 0.0f)
        fail(what + " has negative emission");
      out.baseColor = glm::clamp(out.baseColor, 0.0f, 1.0f);
      out.metallic = glm::clamp(out.metallic, 0.0f, 1.0f);
      out.roughness = glm::clamp(out.roughness, 0.0f, 1.0f);
      if (m.alphaMode == "MASK")
        out.alphaMode = AlphaMode::Mask;
      else if (m.alphaMode == "BLEND")
        out.alphaMode = AlphaMode::Blend;
      out.alphaCutoff = float(m.alphaCutoff);
      out.baseColorTexture = texture(pbr.baseColorTexture.index, true, what + " baseColorTexture");
      out.metallicRoughnessTexture =
          texture(pbr.metallicRoughnessTexture.index, false, what + " metallicRoughnessTexture");
      out.emissiveTexture = texture(m.emissiveTexture.index, true, what + " emissiveTexture");
      scene.materials.push_back(std::move(out));
    }
    // Primitives without a material use the glTF default material, appended last.
    Material fallback;
    fallback.name = "default";
    scene.materials.push_back(fallback);
  }

  void primitive(const tinygltf::Primitive& p, const std::string& what) {
    int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      std::fprintf(stderr, "%s: %s draws points or lines, which carry no surface; skipped\n", scene.sourcePath.c_str(),
                   what.c_str());
      return;
    }
    auto posIt = p.attributes.find("POSITION");
    if (posIt == p.attributes.end()) fail(what + " has no POSITION attribute");
    AccessorView pos = viewAccessor(model, posIt->second, what + " POSITION");
    if (pos.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos.components != 3)
      fail(what + " POSITION must be VEC3 of FLOAT");
    if (pos.count > (1u << 28)) fail(what + " has too many vertices");

    Primitive prim;
    prim.vertexOffset = uint32_t(scene.positions.size());
    prim.vertexCount = uint32_t(pos.count);
    prim.firstIndex = uint32_t(scene.indices.size());
    if (p.material >= 0 && size_t(p.material) >= model.materials.size())
      fail(what + " refers to material " + std::to_string(p.material) + ", which does not exist");
    prim.material = p.material >= 0 ? uint32_t(p.material) : uint32_t(scene.materials.size() - 1);

    for (size_t v = 0; v < pos.count; ++v) {
      glm::vec3 x(readComponent(pos, v, 0), readComponent(pos, v, 1), readComponent(pos, v, 2));
      if (!finite(x)) fail(what + " POSITION " + std::to_string(v) + " is not finite (NaN or Inf)");
      scene.positions.push_back(x);
    }

    bool hasNormals = false;
    auto nrmIt = p.attributes.find("NORMAL");
    if (nrmIt != p.attributes.end()) {
      AccessorView nrm = viewAccessor(model, nrmIt->second, what + " NORMAL");
      if (nrm.components != 3 || nrm.count != pos.count) fail(what + " NORMAL must be VEC3 with one entry per vertex");
      for (size_t v = 0; v < pos.count; ++v) {
        glm::vec3 n(readComponent(nrm, v, 0), readComponent(nrm, v, 1), readComponent(nrm, v, 2));
        if (!finite(n)) fail(what + " NORMAL " + std::to_string(v) + " is not finite (NaN or Inf)");
        float len = glm::length(n);
        scene.normals.push_back(len > 0.0f ? n / len : glm::vec3(0.0f));
      }
      hasNormals = true;
    } else {
      scene.normals.resize(scene.positions.size(), glm::vec3(0.0f));
    }

    auto uvIt = p.attributes.find("TEXCOORD_0");
    if (uvIt != p.attributes.end()) {
      AccessorView uv = viewAccessor(model, uvIt->second, what + " TEXCOORD_0");
      if (uv.components != 2 || uv.count != pos.count)
        fail(what + " TEXCOORD_0 must be VEC2 with one entry per vertex");
      for (size_t v = 0; v < pos.count; ++v) {
        glm::vec2 t(readComponent(uv, v, 0), readComponent(uv, v, 1));
        if (!std::isfinite(t.x) || !std::isfinite(t.y))
          fail(what + " TEXCOORD_0 " + std::to_string(v) + " is not finite");
        scene.uvs.push_back(t);
      }
    } else {
      scene.uvs.resize(scene.positions.size(), glm::vec2(0.0f));
    }

    // Indices (or the implicit 0..n-1), converted to a triangle list.
    std::vector<uint32_t> raw;
    if (p.indices >= 0) {
      AccessorView idx = viewAccessor(model, p.indices, what + " indices");
      if (idx.components != 1 || (idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                  idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                  idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail(what + " indices must be SCALAR unsigned integers");
      raw.resize(idx.count);
      for (size_t i = 0; i < idx.count; ++i) {
        raw[i] = readIndex(idx, i);
        if (raw[i] >= pos.count)
          fail(what + " index " + std::to_string(i) + " is " + std::to_string(raw[i]) + ", out of range for " +
               std::to_string(pos.count) + " vertices");
      }
    } else {
      raw.resize(pos.count);
      for (size_t i = 0; i < pos.count; ++i) raw[i] = uint32_t(i);
    }
    std::vector<uint32_t> tris;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      tris.assign(raw.begin(), raw.end() - raw.size() % 3);
    } else {
      for (size_t i = 2; i < raw.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
          tris.insert(tris.end(), {raw[0], raw[i - 1], raw[i]});
        else if (i % 2 == 0)
          tris.insert(tris.end(), {raw[i - 2], raw[i - 1], raw[i]});
        else
          tris.insert(tris.end(), {raw[i - 1], raw[i - 2], raw[i]});  // keep the winding of odd strip triangles
      }
    }
    skinInfluences(p, pos.count, what);
    if (!p.targets.empty() && !warnedMorphTargets) {
      std::fprintf(stderr, "%s: warning: %s has morph targets, which are not played (the mesh keeps its base shape)\n",
                   scene.sourcePath.c_str(), what.c_str());
      warnedMorphTargets = true;
    }
    scene.indices.insert(scene.indices.end(), tris.begin(), tris.end());
    prim.indexCount = uint32_t(tris.size());
    scene.primitives.push_back(prim);
    if (!hasNormals) generateNormals(scene, prim);
    // Zero-length normals in the file fall back to generated ones for that primitive.
    for (uint32_t v = 0; v < prim.vertexCount; ++v)
      if (scene.normals[prim.vertexOffset + v] == glm::vec3(0.0f)) {
        generateNormals(scene, prim);
        break;
      }
  }

  // JOINTS_0 and WEIGHTS_0 of a primitive whose vertices were just appended (zero where it has none).
  void skinInfluences(const tinygltf::Primitive& p, size_t vertices, const std::string& what) {
    SceneAnimations& a = scene.gltf;
    const size_t first = scene.positions.size() - vertices;
    a.vertexJoints.resize(scene.positions.size(), glm::uvec4(0));
    a.vertexWeights.resize(scene.positions.size(), glm::vec4(0.0f));
    auto joints = p.attributes.find("JOINTS_0"), weights = p.attributes.find("WEIGHTS_0");
    if (joints == p.attributes.end() && weights == p.attributes.end()) return;
    if (joints == p.attributes.end() || weights == p.attributes.end())
      fail(what + " has one of JOINTS_0 and WEIGHTS_0 without the other");
    if (p.attributes.count("JOINTS_1") && !warnedExtraInfluences) {
      std::fprintf(stderr, "%s: warning: %s has JOINTS_1/WEIGHTS_1; only the first four influences are played\n",
                   scene.sourcePath.c_str(), what.c_str());
      warnedExtraInfluences = true;
    }
    AccessorView j = viewAccessor(model, joints->second, what + " JOINTS_0"),
                 w = viewAccessor(model, weights->second, what + " WEIGHTS_0");
    if (j.components != 4 || j.count != vertices ||
        (j.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         j.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
      fail(what + " JOINTS_0 must be VEC4 of unsigned bytes or shorts, one per vertex");
    if (w.components != 4 || w.count != vertices) fail(what + " WEIGHTS_0 must be VEC4, one per vertex");
    for (size_t v = 0; v < vertices; ++v) {
      glm::vec4 weight;
      for (int k = 0; k < 4; ++k) {
        a.vertexJoints[first + v][k] = uint32_t(readComponent(j, v, k));
        weight[k] = readComponent(w, v, k);
      }
      const float sum = weight.x + weight.y + weight.z + weight.w;
      if (!std::isfinite(sum) || glm::any(glm::lessThan(weight, glm::vec4(0.0f))) || !(sum > 0.0f))
        fail(what + " WEIGHTS_0 " + std::to_string(v) + " is negative, not finite or all zero");
      a.vertexWeights[first + v] = weight / sum;  // glTF asks for a sum of 1; rounding in the file is forgiven
    }
  }

  int mesh(int index, bool skinned = false) {
    if (index < 0 || size_t(index) >= model.meshes.size())
      fail("a node refers to mesh " + std::to_string(index) + ", which does not exist");
    if (skinned) return newMesh(index);  // each skinned node poses its own copy
    if (meshMap[index] >= 0) return meshMap[index];
    meshMap[index] = newMesh(index);
    return meshMap[index];
  }

  int newMesh(int index) {
    const tinygltf::Mesh& m = model.meshes[index];
    Mesh out;
    out.name = m.name;
    out.firstPrimitive = uint32_t(scene.primitives.size());
    for (size_t i = 0; i < m.primitives.size(); ++i)
      primitive(m.primitives[i],
                "mesh " + std::to_string(index) + " ('" + m.name + "') primitive " + std::to_string(i));
    out.primitiveCount = uint32_t(scene.primitives.size()) - out.firstPrimitive;
    scene.meshes.push_back(out);
    return int(scene.meshes.size()) - 1;
  }

  // The node's rest pose as the file gives it: a matrix, or translation, rotation and scale.
  SceneNode restPose(const tinygltf::Node& n, const std::string& what) {
    SceneNode out;
    if (n.matrix.size() == 16) {
      out.hasMatrix = true;
      for (int i = 0; i < 16; ++i) glm::value_ptr(out.matrix)[i] = float(n.matrix[i]);
      return out;
    }
    if (!n.matrix.empty()) fail(what + " has a matrix that is not 16 numbers");
    out.translation = glm::vec3(float(numberOr(n.translation, 0, 0)), float(numberOr(n.translation, 1, 0)),
                                float(numberOr(n.translation, 2, 0)));
    const glm::quat r(float(numberOr(n.rotation, 3, 1)), float(numberOr(n.rotation, 0, 0)),
                      float(numberOr(n.rotation, 1, 0)), float(numberOr(n.rotation, 2, 0)));
    const float rl = glm::length(r);
    if (!(rl > 0.0f)) fail(what + " has a zero rotation quaternion");
    out.rotation = r / rl;
    out.scale =
        glm::vec3(float(numberOr(n.scale, 0, 1)), float(numberOr(n.scale, 1, 1)), float(numberOr(n.scale, 2, 1)));
    return out;
  }

  void node(int index, const glm::mat4& parent, std::vector<int>& path, int parentNode = -1) {
    if (index < 0 || size_t(index) >= model.nodes.size())
      fail("the node hierarchy refers to node " + std::to_string(index) + ", which does not exist");
    if (std::find(path.begin(), path.end(), index) != path.end())
      fail("node " + std::to_string(index) + " is its own ancestor (the hierarchy has a cycle)");
    if (path.size() > 256) fail("the node hierarchy is deeper than 256 levels");
    const tinygltf::Node& n = model.nodes[index];
    std::string what = "node " + std::to_string(index) + " ('" + n.name + "')";
    SceneNode& record = scene.gltf.nodes[size_t(index)];
    record = restPose(n, what);
    record.parent = parentNode;
    glm::mat4 world = parent * localMatrix(record);
    for (int c = 0; c < 4; ++c)
      if (!finite(glm::vec3(world[c])) || !std::isfinite(world[c][3])) fail(what + " has a non-finite transform");

    if (n.mesh >= 0 && n.skin >= 0) {
      // glTF places a skinned mesh by its joints alone: the node's own transform is ignored.
      if (size_t(n.skin) >= model.skins.size())
        fail(what + " refers to skin " + std::to_string(n.skin) + ", which does not exist");
      const uint32_t m = uint32_t(mesh(n.mesh, true));
      scene.meshes[m].deformable = true;
      scene.gltf.skinnedMeshes.push_back({m, uint32_t(n.skin)});
      scene.instances.push_back({n.name, m, glm::mat4(1.0f)});
    } else if (n.mesh >= 0) {
      record.instances.push_back(int(scene.instances.size()));
      scene.instances.push_back({n.name, uint32_t(mesh(n.mesh)), world});
    }
    if (n.camera >= 0) {
      if (size_t(n.camera) >= model.cameras.size()) fail(what + " refers to a camera that does not exist");
      const tinygltf::Camera& c = model.cameras[n.camera];
      if (c.type == "perspective") {
        Camera cam;
        cam.name = c.name.empty() ? n.name : c.name;
        // Cameras ignore scale: re-orthonormalise the rotation, keep the translation.
        glm::vec3 x(world[0]), y(world[1]);
        glm::vec3 z = glm::cross(x, y);
        if (!(glm::length(x) > 0.0f) || !(glm::length(z) > 0.0f)) fail(what + " has a degenerate camera transform");
        x = glm::normalize(x);
        z = glm::normalize(z);
        y = glm::cross(z, x);
        cam.worldFromView = glm::mat4(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f), world[3]);
        cam.yfov = float(c.perspective.yfov);
        cam.znear = float(c.perspective.znear);
        cam.zfar = float(c.perspective.zfar);
        if (!(cam.yfov > 0.0f && cam.yfov < 3.14f)) fail(what + " camera has an invalid yfov");
        if (!(cam.znear > 0.0f)) fail(what + " camera has an invalid znear");
        scene.cameras.push_back(cam);
      } else {
        std::fprintf(stderr, "%s: %s has a %s camera; only perspective cameras are used\n", scene.sourcePath.c_str(),
                     what.c_str(), c.type.c_str());
      }
    }
    auto lightExt = n.extensions.find("KHR_lights_punctual");
    if (lightExt != n.extensions.end() && lightExt->second.Has("light")) {
      int li = lightExt->second.Get("light").GetNumberAsInt();
      if (li < 0 || size_t(li) >= model.lights.size()) fail(what + " refers to a punctual light that does not exist");
      const tinygltf::Light& l = model.lights[li];
      PunctualLight out;
      out.name = l.name;
      if (l.type == "point")
        out.type = LightType::Point;
      else if (l.type == "spot")
        out.type = LightType::Spot;
      else if (l.type == "directional")
        out.type = LightType::Directional;
      else
        fail("light " + std::to_string(li) + " has unknown type '" + l.type + "'");
      glm::vec3 color(float(numberOr(l.color, 0, 1)), float(numberOr(l.color, 1, 1)), float(numberOr(l.color, 2, 1)));
      out.intensity = color * float(l.intensity);
      if (!finite(out.intensity) || glm::any(glm::lessThan(out.intensity, glm::vec3(0.0f))))
        fail("light " + std::to_string(li) + " has a negative or non-finite intensity");
      out.range = float(l.range);
      out.innerConeAngle = float(l.spot.innerConeAngle);
      out.outerConeAngle = float(l.spot.outerConeAngle);
      out.position = glm::vec3(world[3]);
      glm::vec3 dir = -glm::vec3(world[2]);
      if (!(glm::length(dir) > 0.0f)) fail(what + " has a degenerate light direction");
      out.direction = glm::normalize(dir);
      record.lights.push_back(int(scene.lights.size()));
      scene.lights.push_back(out);
    }
    path.push_back(index);
    for (int child : n.children) node(child, world, path, index);
    path.pop_back();
  }
};

// tinygltf's file access made strict: a URI is a path as written (no shell-style expansion), and only a
// regular file of at most kMaxExternalFileBytes is read. Its own reader takes a directory's size as -1
// and allocates that (a URI naming a directory ended the program with std::bad_alloc).
constexpr uintmax_t kMaxExternalFileBytes = uintmax_t(4) << 30;  // 4 GiB: beyond any buffer or image we take

bool regularFileExists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string pathAsWritten(const std::string& path, void*) { return path; }

bool readRegularFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  auto failWith = [&](const std::string& why) {
    if (err) *err += path + ": " + why + "\n";
    return false;
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return failWith("not a regular file");
  const uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) return failWith("its size cannot be read (" + ec.message() + ")");
  if (bytes > kMaxExternalFileBytes) return failWith(std::to_string(bytes) + " bytes, more than the 4 GiB we read");
  std::ifstream file(path, std::ios::binary);
  out->resize(size_t(bytes));
  if (!file || (bytes > 0 && !file.read(reinterpret_cast<char*>(out->data()), std::streamsize(bytes))))
    return failWith("cannot be read");
  return true;
}

bool refuseWrite(std::string* err, const std::string& path, const std::vector<unsigned char>&, void*) {
  if (err) *err += path + ": the loader writes no files\n";
  return false;
}

}  // namespace

bool loadGltf(const std::string& path, Scene& scene, std::string& error) {
  scene = Scene{};
  scene.sourcePath = path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    error = path + ": file not found";
    return false;
  }
  tinygltf::TinyGLTF gltf;
  gltf.SetFsCallbacks({regularFileExists, pathAsWritten, readRegularFile, refuseWrite, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  bool binary = path.size() >= 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  bool ok = false;
  try {
    ok =
        binary ? gltf.LoadBinaryFromFile(&model, &err, &warn, path) : gltf.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {  // memory for what the file declares, or tinygltf's own throws
    error = path + ": cannot be loaded (" + e.what() + ")";
    return false;
  }
  if (!ok || !err.empty()) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    error = path + ": " + (err.empty() ? std::string("not a valid glTF file") : err);
    return false;
  }
  try {
    if (model.asset.version.rfind("2.", 0) != 0)
      fail("asset.version is '" + model.asset.version + "'; only glTF 2.x is supported");
    for (const std::string& ext : model.extensionsRequired)
      if (std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), ext) ==
          std::end(kSupportedExtensions))
        fail("requires the extension " + ext + ", which is not supported");
    for (size_t b = 0; b < model.buffers.size(); ++b)
      if (model.buffers[b].data.empty())
        fail("buffer " + std::to_string(b) + " ('" + model.buffers[b].uri + "') is missing or empty");

    Loader loader{model, scene, std::vector<int>(model.meshes.size(), -1),
                  std::vector<std::array<int, 2>>(model.images.size(), {-1, -1})};
    loader.materials();
    std::vector<int> roots;
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (!model.scenes.empty()) {
      if (size_t(sceneIndex) >= model.scenes.size()) fail("the default scene does not exist");
      roots = model.scenes[sceneIndex].nodes;
    } else {
      // No scenes: every node that is nobody's child is a root.
      std::vector<bool> isChild(model.nodes.size(), false);
      for (const tinygltf::Node& n : model.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < isChild.size()) isChild[c] = true;
      for (size_t i = 0; i < model.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(int(i));
    }
    scene.gltf.nodes.assign(model.nodes.size(), SceneNode{});
    std::vector<int> path2;
    for (int r : roots) loader.node(r, glm::mat4(1.0f), path2);
    loader.skins();
    loader.animations();
    if (!scene.gltf.skinnedMeshes.empty()) {  // the skinned meshes at t = 0, from their bind pose
      scene.gltf.bindPositions = scene.positions;
      scene.gltf.bindNormals = scene.normals;
      poseGltfAnimations(scene, 0.0f);
      skinOnCpu(scene);
    }
  } catch (const LoadError& e) {
    error = path + ": " + e.message;
    scene = Scene{};
    return false;
  }
  if (scene.cameras.empty()) scene.cameras.push_back(defaultCamera(scene.worldBounds()));
  return true;
}

}  // namespace engine
