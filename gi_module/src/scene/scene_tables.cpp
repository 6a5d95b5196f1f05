#include "scene/scene_tables.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "scene/light_tree.h"
#include "scene/morton_order.h"
#include "scene/sky_tables.h"

namespace gi {
namespace {

std::string at(const char* what, size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

bool finite(std::span<const float> values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}
bool finiteNonNegative(std::span<const float> values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v) && v >= 0.0f; });
}

float luminance(const glm::vec3& c) { return gi::luminance(c.x, c.y, c.z); }

std::string checkTexture(int32_t texture, size_t count, const std::string& field) {
  if (texture < -1 || (texture >= 0 && size_t(texture) >= count))
    return field + " = " + std::to_string(texture) + " is not −1 or below the texture count " + std::to_string(count);
  return {};
}

std::string checkMaterial(const MaterialDesc& m, size_t textures, const std::string& where) {
  if (!finiteNonNegative(m.baseColor)) return where + ".baseColor must be finite and ≥ 0";
  if (!(m.metallic >= 0.0f && m.metallic <= 1.0f))
    return where + ".metallic = " + std::to_string(m.metallic) + " is outside [0, 1]";
  if (!(m.roughness >= 0.0f && m.roughness <= 1.0f))
    return where + ".roughness = " + std::to_string(m.roughness) + " is outside [0, 1]";
  if (!finiteNonNegative(m.emissive) || !std::isfinite(m.emissiveStrength) || m.emissiveStrength < 0.0f)
    return where + ": emissive and emissiveStrength must be finite and ≥ 0";
  if (!(m.alphaCutoff >= 0.0f && m.alphaCutoff <= 1.0f))
    return where + ".alphaCutoff = " + std::to_string(m.alphaCutoff) + " is outside [0, 1]";
  if (uint32_t(m.alphaMode) > uint32_t(AlphaMode::Blend)) return where + ".alphaMode is not Opaque, Mask or Blend";
  for (auto [t, name] : {std::pair{m.baseColorTexture, ".baseColorTexture"},
                         std::pair{m.metallicRoughnessTexture, ".metallicRoughnessTexture"},
                         std::pair{m.emissiveTexture, ".emissiveTexture"}})
    if (std::string e = checkTexture(t, textures, where + name); !e.empty()) return e;
  return {};
}

gpu::GpuMaterial gpuMaterial(const MaterialDesc& m, glm::vec3& emission) {
  emission = glm::vec3(m.emissive[0], m.emissive[1], m.emissive[2]) * m.emissiveStrength;
  const bool emissive = emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
  // A GGX lobe is added only where it changes the result noticeably.
  const bool glossy = gpu::materialHasGlossyLobe(m.metallic, m.roughness) || m.metallicRoughnessTexture >= 0;
  auto texture = [](int32_t t) { return t >= 0 ? uint32_t(t) : gpu::NO_TEXTURE; };
  gpu::GpuMaterial g{};
  g.baseColor = glm::vec4(m.baseColor[0], m.baseColor[1], m.baseColor[2], m.baseColor[3]);
  g.emission = emission;
  g.metallic = m.metallic;
  g.roughness = m.roughness;
  g.alphaCutoff = m.alphaCutoff;
  g.baseColorTexture = texture(m.baseColorTexture);
  g.metallicRoughnessTexture = texture(m.metallicRoughnessTexture);
  g.emissiveTexture = texture(m.emissiveTexture);
  g.flags = (glossy ? gpu::MATERIAL_FLAG_GLOSSY : 0u) |
            (m.alphaMode == AlphaMode::Mask ? gpu::MATERIAL_FLAG_ALPHA_MASK : 0u) |
            (emissive ? gpu::MATERIAL_FLAG_EMISSIVE : 0u);
  return g;
}

std::string checkSky(const SkyDesc& sky) {
  if (!finiteNonNegative(sky.radiance)) return "contents.sky.radiance must be finite and ≥ 0";
  if (!sky.map) return {};
  if (sky.width == 0 || sky.height == 0)
    return "contents.sky: a map of " + std::to_string(sky.width) + "×" + std::to_string(sky.height) + " texels";
  if (sky.channels != 3 && sky.channels != 4)
    return "contents.sky.channels = " + std::to_string(sky.channels) + " (3 or 4 expected)";
  for (size_t i = 0; i < size_t(sky.width) * sky.height; ++i)
    if (!finiteNonNegative(std::span(sky.map + i * sky.channels, 3)))
      return "contents.sky.map texel (" + std::to_string(i % sky.width) + ", " + std::to_string(i / sky.width) +
             ") is not finite and ≥ 0";
  return {};
}

// Appends one mesh's primitives to the pool.
std::string packMesh(const MeshDesc& mesh, size_t materialCount, const std::string& where, PackedScene& out) {
  if (mesh.vertexCount > 0 && (!mesh.positions || !mesh.normals))
    return where + ": positions and normals are required (" + std::to_string(mesh.vertexCount) + " vertices)";
  if (mesh.indexCount > 0 && !mesh.indices)
    return where + ".indices is null with indexCount " + std::to_string(mesh.indexCount);
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const PrimitiveDesc& prim = mesh.primitives[p];
    const std::string field = where + at(".primitives", p);
    if (prim.indexCount % 3 != 0)
      return field + ".indexCount = " + std::to_string(prim.indexCount) + " is not a multiple of 3";
    if (uint64_t(prim.firstIndex) + prim.indexCount > mesh.indexCount)
      return field + ": indices [" + std::to_string(prim.firstIndex) + ", +" + std::to_string(prim.indexCount) +
             ") run past indexCount " + std::to_string(mesh.indexCount);
    if (uint64_t(prim.firstVertex) + prim.vertexCount > mesh.vertexCount)
      return field + ": vertices [" + std::to_string(prim.firstVertex) + ", +" + std::to_string(prim.vertexCount) +
             ") run past vertexCount " + std::to_string(mesh.vertexCount);
    if (prim.material >= materialCount)
      return field + ".material = " + std::to_string(prim.material) + " is not below the material count " +
             std::to_string(materialCount);
    for (uint32_t i = 0; i < prim.indexCount; ++i)
      if (mesh.indices[prim.firstIndex + i] >= prim.vertexCount)
        return field + ": index " + std::to_string(mesh.indices[prim.firstIndex + i]) + " is not below vertexCount " +
               std::to_string(prim.vertexCount);
    gpu::GpuGeometry g{uint32_t(out.indices.size()), uint32_t(out.positions.size()), prim.material,
                       prim.indexCount / 3};
    out.geometries.push_back(g);
    out.geometryVertexCount.push_back(prim.vertexCount);
    out.geometryFirstVertex.push_back(prim.firstVertex);
    out.indices.insert(out.indices.end(), mesh.indices + prim.firstIndex,
                       mesh.indices + prim.firstIndex + prim.indexCount);
    for (uint32_t v = prim.firstVertex; v < prim.firstVertex + prim.vertexCount; ++v) {
      const float* pos = element(mesh.positions, mesh.positionStride, 12, v);
      const float* nrm = element(mesh.normals, mesh.normalStride, 12, v);
      out.positions.emplace_back(pos[0], pos[1], pos[2]);
      out.normals.emplace_back(nrm[0], nrm[1], nrm[2]);
      if (mesh.uvs) {
        const float* uv = element(mesh.uvs, mesh.uvStride, 8, v);
        out.uvs.emplace_back(uv[0], uv[1]);
      } else {
        out.uvs.emplace_back(0.0f);
      }
    }
    mortonSortTriangles(std::span(out.positions).subspan(g.vertexOffset, prim.vertexCount),
                        std::span(out.indices).subspan(g.firstIndex, prim.indexCount));
  }
  return {};
}

}  // namespace

const float* element(const float* base, uint32_t stride, uint32_t packedSize, uint32_t i) {
  const uint32_t s = stride ? stride : packedSize;
  return reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) + size_t(s) * i);
}

glm::mat4 toMat4(const float (&m)[16]) {
  glm::mat4 r;
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) r[c][row] = m[c * 4 + row];
  return r;
}

std::string packScene(const SceneContents& contents, PackedScene& out) {
  out = PackedScene{};
  for (size_t i = 0; i < contents.textures.size(); ++i)
    if (!contents.textures[i].view || !contents.textures[i].sampler)
      return at("contents.textures", i) + ": view and sampler are required";
  out.materialEmission.resize(contents.materials.size());
  for (size_t i = 0; i < contents.materials.size(); ++i) {
    if (std::string e = checkMaterial(contents.materials[i], contents.textures.size(), at("contents.materials", i));
        !e.empty())
      return e;
    out.materials.push_back(gpuMaterial(contents.materials[i], out.materialEmission[i]));
  }
  for (size_t m = 0; m < contents.meshes.size(); ++m) {
    out.meshFirstGeometry.push_back(uint32_t(out.geometries.size()));
    out.meshGeometryCount.push_back(uint32_t(contents.meshes[m].primitives.size()));
    out.meshDeformable.push_back(contents.meshes[m].deformable ? 1 : 0);
    if (std::string e = packMesh(contents.meshes[m], contents.materials.size(), at("contents.meshes", m), out);
        !e.empty())
      return e;
  }
  if (!finite(std::span(reinterpret_cast<const float*>(out.positions.data()), out.positions.size() * 3)))
    return "contents.meshes: a vertex position is not finite";
  for (size_t m = 0; m < contents.meshes.size(); ++m) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (uint32_t id = out.meshFirstGeometry[m]; id < out.meshFirstGeometry[m] + out.meshGeometryCount[m]; ++id)
      for (uint32_t v = 0; v < out.geometryVertexCount[id]; ++v) {
        lo = glm::min(lo, out.positions[out.geometries[id].vertexOffset + v]);
        hi = glm::max(hi, out.positions[out.geometries[id].vertexOffset + v]);
      }
    out.meshCentres.push_back(lo.x <= hi.x ? 0.5f * (lo + hi) : glm::vec3(0.0f));
  }
  // Only materials some primitive uses decide which passes run.
  for (const gpu::GpuGeometry& g : out.geometries) {
    out.hasAlphaMask |= (out.materials[g.material].flags & gpu::MATERIAL_FLAG_ALPHA_MASK) != 0;
    out.hasGlossyMaterials |= (out.materials[g.material].flags & gpu::MATERIAL_FLAG_GLOSSY) != 0;
  }
  if (std::string e = checkSky(contents.sky); !e.empty()) return e;
  out.skyMeanLuminance =
      contents.sky.map ? meanLuminance(contents.sky.map, contents.sky.width, contents.sky.height, contents.sky.channels)
                       : 1.0f;
  return {};
}

std::string checkInstances(const PackedScene& packed, std::span<const InstanceDesc> instances, const char* what) {
  for (size_t i = 0; i < instances.size(); ++i) {
    if (instances[i].mesh >= packed.meshFirstGeometry.size())
      return at(what, i) + ".mesh = " + std::to_string(instances[i].mesh) + " is not below the mesh count " +
             std::to_string(packed.meshFirstGeometry.size());
    if (!finite(instances[i].worldFromObject)) return at(what, i) + ".worldFromObject is not finite";
  }
  return {};
}

std::string checkLights(std::span<const LightDesc> lights, const char* what) {
  for (size_t i = 0; i < lights.size(); ++i) {
    const LightDesc& l = lights[i];
    if (uint32_t(l.type) > uint32_t(LightType::Directional))
      return at(what, i) + ".type is not Point, Spot or Directional";
    if (!finite(l.position) || !finite(l.direction)) return at(what, i) + ": position and direction must be finite";
    if (!finiteNonNegative(l.intensity) || !std::isfinite(l.range) || l.range < 0.0f)
      return at(what, i) + ": intensity and range must be finite and ≥ 0";
    if (!std::isfinite(l.innerConeAngle) || !std::isfinite(l.outerConeAngle))
      return at(what, i) + ": cone angles must be finite";
  }
  return {};
}

namespace {

// The directions a triangle sends light in: its geometric normal, turned to the side its vertex normals
// are on (giTriangleNormals turns it to the shading normal's); every direction where they disagree or it
// has no area. One-sided emission: a cosine emitter (cosFalloff 0).
DirectionCone triangleCone(const glm::vec3 (&v)[3], const glm::vec3 (&n)[3]) {
  const glm::dvec3 g = glm::cross(glm::dvec3(v[1] - v[0]), glm::dvec3(v[2] - v[0]));
  if (!(glm::dot(g, g) > 0.0)) return {glm::dvec3(0.0, 0.0, 1.0), std::numbers::pi};
  int front = 0, back = 0;
  for (const glm::vec3& normal : n) {
    const double d = glm::dot(g, glm::dvec3(normal));
    front += d >= 0.0;
    back += d <= 0.0;
  }
  if (front == 3) return {glm::normalize(g), 1e-3};  // 1e-3 rad: as a spot's margin, for float rounding
  if (back == 3) return {-glm::normalize(g), 1e-3};
  return {glm::normalize(g), std::numbers::pi};
}

}  // namespace

EmissiveTable emissiveTable(const PackedScene& packed, std::span<const InstanceDesc> instances) {
  EmissiveTable table;
  std::vector<EmitterBounds> bounds;
  for (uint32_t i = 0; i < instances.size(); ++i) {
    const glm::mat4 world = toMat4(instances[i].worldFromObject);
    const glm::mat3 normalWorld = glm::transpose(glm::inverse(glm::mat3(world)));
    const uint32_t first = packed.meshFirstGeometry[instances[i].mesh];
    for (uint32_t id = first; id < first + packed.meshGeometryCount[instances[i].mesh]; ++id) {
      const gpu::GpuGeometry& geo = packed.geometries[id];
      const glm::vec3 emission = packed.materialEmission[geo.material];
      if (!(emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f)) continue;
      for (uint32_t t = 0; t < geo.triangleCount; ++t) {
        glm::vec3 v[3], n[3];
        for (int k = 0; k < 3; ++k) {
          const uint32_t vertex = geo.vertexOffset + packed.indices[geo.firstIndex + 3 * t + k];
          v[k] = glm::vec3(world * glm::vec4(packed.positions[vertex], 1.0f));
          n[k] = normalWorld * packed.normals[vertex];
        }
        const double area = 0.5 * double(glm::length(glm::cross(v[1] - v[0], v[2] - v[0])));
        double w = area * double(luminance(emission));
        if (!(w > 0.0) || !std::isfinite(w)) w = 0.0;  // never picked: a triangle without area is never hit
        // Every triangle keeps its entry, so an (instance, geometry, triangle) finds its own by search.
        table.triangles.push_back({i, id, t, 0.0f});
        bounds.push_back(
            {glm::min(v[0], glm::min(v[1], v[2])), glm::max(v[0], glm::max(v[1], v[2])), triangleCone(v, n), w, 0.0f});
      }
    }
  }
  double total = 0.0;
  for (const EmitterBounds& b : bounds) total += b.power;
  if (!(total > 0.0)) return table;  // nothing to pick: the scene's constants hold no emissive triangle
  double running = 0.0;
  size_t last = 0;
  for (size_t k = 0; k < table.triangles.size(); ++k) {
    running += bounds[k].power;
    table.triangles[k].cdf = float(running / total);
    if (bounds[k].power > 0.0) last = k;
  }
  // Rounding never leaves u ∈ [0, 1) without a triangle, nor picks one after the last with area.
  for (size_t k = last; k < table.triangles.size(); ++k) table.triangles[k].cdf = 1.0f;
  std::vector<uint32_t> order(table.triangles.size());
  for (uint32_t k = 0; k < order.size(); ++k) order[k] = k;
  table.nodes = buildLightTree(bounds, std::move(order));
  table.totalPower = float(total);
  return table;
}

bool meshEmits(const PackedScene& packed, uint32_t mesh) {
  const uint32_t first = packed.meshFirstGeometry[mesh];
  for (uint32_t id = first; id < first + packed.meshGeometryCount[mesh]; ++id)
    if (packed.materials[packed.geometries[id].material].flags & gpu::MATERIAL_FLAG_EMISSIVE) return true;
  return false;
}

std::vector<uint32_t> emissiveTableWords(const EmissiveTable& t) {
  const size_t n = t.pickable();
  std::vector<uint32_t> words(emissiveTableCapacityWords(n));
  if (n == 0) return words;  // no triangle to pick (memcpy from an empty vector's null data is undefined)
  std::memcpy(words.data(), t.triangles.data(), n * sizeof(gpu::GpuEmissiveTriangle));
  const size_t leafWord = (n * sizeof(gpu::GpuEmissiveTriangle) + t.nodes.size() * sizeof(gpu::GpuLightNode)) / 4;
  std::memcpy(words.data() + n * 4, t.nodes.data(), t.nodes.size() * sizeof(gpu::GpuLightNode));
  for (uint32_t i = 0; i < t.nodes.size(); ++i)
    if (t.nodes[i].child & gpu::LIGHT_NODE_LEAF) words[leafWord + (t.nodes[i].child & ~gpu::LIGHT_NODE_LEAF)] = i;
  return words;
}

namespace {

// A light's power by the measure LIGHT_SAMPLER_POWER picks it by (any positive weight gives the same
// expectation; power gives the bright ones their share of the rays): intensity over the sphere (point)
// or the cone (spot), irradiance over the disc of the scene's radius (directional).
double samplingPower(const LightDesc& l, float sceneExtent) {
  const double brightness = double(luminance(glm::vec3(l.intensity[0], l.intensity[1], l.intensity[2])));
  switch (l.type) {
    case LightType::Spot:
      return 2.0 * std::numbers::pi * (1.0 - std::cos(std::min(double(l.outerConeAngle), std::numbers::pi))) *
             brightness;
    case LightType::Directional:
      return std::numbers::pi * 0.25 * double(sceneExtent) * double(sceneExtent) * brightness;
    default: return 4.0 * std::numbers::pi * brightness;
  }
}

gpu::GpuPunctualLight gpuLight(const LightDesc& l) {
  gpu::GpuPunctualLight g{};
  g.position = glm::vec3(l.position[0], l.position[1], l.position[2]);
  g.type = uint32_t(l.type);
  g.direction = glm::vec3(l.direction[0], l.direction[1], l.direction[2]);
  g.range = l.range;
  g.intensity = glm::vec3(l.intensity[0], l.intensity[1], l.intensity[2]);
  g.cosInner = std::cos(l.innerConeAngle);
  g.cosOuter = std::cos(l.outerConeAngle);
  return g;
}

// Each light's cdf: its share of the power up to it (alike when all are black).
void fillCdf(std::vector<gpu::GpuPunctualLight>& table, const std::vector<double>& power) {
  double total = 0.0;
  for (double p : power) total += p;
  double sum = 0.0;
  for (size_t i = 0; i < table.size(); ++i) {
    sum += total > 0.0 ? power[i] : 1.0;
    table[i].cdf = float(sum / (total > 0.0 ? total : double(table.size())));
  }
  if (!table.empty()) table.back().cdf = 1.0f;  // rounding never leaves u ∈ [0, 1) without a light
}

// How far a spot's cone is widened in the tree: the shaders' float arithmetic must never rule out a
// light a surface is inside the cone of (radians).
constexpr double kLightConeMargin = 1e-3;

// The directions a light sends light in: a spot's outer cone (widened), every direction for a point light.
DirectionCone lightCone(const gpu::GpuPunctualLight& l) {
  if (l.type != gpu::PUNCTUAL_SPOT) return {glm::dvec3(0.0, 0.0, 1.0), std::numbers::pi};
  const double outer = std::acos(std::clamp(double(l.cosOuter), -1.0, 1.0));
  return {glm::normalize(glm::dvec3(l.direction)), std::min(outer + kLightConeMargin, std::numbers::pi)};
}

}  // namespace

LightTable lightTable(std::span<const LightDesc> lights, float sceneExtent, uint32_t cutSize) {
  LightTable t;
  // Directional lights first: under LIGHT_SAMPLER_TREE they are picked apart from the tree.
  std::vector<double> power;
  for (int directional = 1; directional >= 0; --directional)
    for (const LightDesc& l : lights)
      if ((l.type == LightType::Directional) == bool(directional)) {
        t.lights.push_back(gpuLight(l));
        power.push_back(samplingPower(l, sceneExtent));
        t.directionalCount += uint32_t(directional);
      }
  fillCdf(t.lights, power);
  if (t.lights.size() > t.directionalCount) {
    std::vector<EmitterBounds> bounds(t.lights.size());
    std::vector<uint32_t> order;
    for (uint32_t i = t.directionalCount; i < t.lights.size(); ++i) {
      bounds[i] = {t.lights[i].position, t.lights[i].position, lightCone(t.lights[i]), power[i], 1.0f};
      order.push_back(i);
    }
    t.nodes = buildLightTree(bounds, std::move(order));
    t.cut = treeCut(t.nodes, std::max(cutSize, 1u));
  }
  return t;
}

bool picksPunctualLights(const gpu::GpuSceneConstants& c) {
  const uint32_t positional = c.punctualLightCount - c.directionalLightCount;
  return (c.lightSampler == gpu::LIGHT_SAMPLER_POWER && c.punctualLightCount > 1) ||
         (c.lightSampler == gpu::LIGHT_SAMPLER_TREE && positional > c.lightCutSize);
}

void setLightFacts(const gpu::GpuSceneConstants& c, SceneDesc& facts) {
  facts.lightSampler = c.lightSampler;
  for (uint32_t sampler = gpu::LIGHT_SAMPLER_ALL; sampler <= gpu::LIGHT_SAMPLER_TREE; ++sampler) {
    gpu::GpuSceneConstants with = c;
    with.lightSampler = sampler;
    facts.picksPunctualLightsWith[sampler] = picksPunctualLights(with);
  }
}

std::vector<uint32_t> lightTableWords(const LightTable& t) {
  const size_t lightWords = t.lights.size() * sizeof(gpu::GpuPunctualLight) / 4;
  const size_t nodeWords = t.nodes.size() * sizeof(gpu::GpuLightNode) / 4;
  std::vector<uint32_t> words((lightWords + nodeWords + t.cut.size() + 3) / 4 * 4);  // whole texels
  if (!t.lights.empty()) std::memcpy(words.data(), t.lights.data(), lightWords * 4);
  if (!t.nodes.empty()) std::memcpy(words.data() + lightWords, t.nodes.data(), nodeWords * 4);
  std::copy(t.cut.begin(), t.cut.end(), words.begin() + ptrdiff_t(lightWords + nodeWords));
  return words;
}

std::vector<gpu::GpuInstance> gpuInstances(const PackedScene& packed, std::span<const InstanceDesc> instances,
                                           std::span<const glm::mat4> previous) {
  std::vector<gpu::GpuInstance> out;
  for (size_t i = 0; i < instances.size(); ++i) {
    const glm::mat4 world = toMat4(instances[i].worldFromObject);
    gpu::GpuInstance g{};
    g.worldFromObject = world;
    g.normalWorldFromObject = glm::mat4(glm::transpose(glm::inverse(glm::mat3(world))));
    g.previousWorldFromObject = i < previous.size() ? previous[i] : world;
    g.firstGeometry = packed.meshFirstGeometry[instances[i].mesh];
    g.geometryCount = packed.meshGeometryCount[instances[i].mesh];
    out.push_back(g);
  }
  return out;
}

std::vector<BvhMesh> bvhMeshes(const PackedScene& packed) {
  std::vector<BvhMesh> meshes(packed.meshFirstGeometry.size());
  for (size_t m = 0; m < meshes.size(); ++m) {
    meshes[m].deformable = packed.meshDeformable[m] != 0;
    for (uint32_t id = packed.meshFirstGeometry[m]; id < packed.meshFirstGeometry[m] + packed.meshGeometryCount[m];
         ++id) {
      const gpu::GpuGeometry& g = packed.geometries[id];
      meshes[m].geometries.push_back({g.firstIndex, g.triangleCount, g.vertexOffset, id});
    }
  }
  return meshes;
}

std::vector<BvhInstance> bvhInstances(std::span<const InstanceDesc> instances, std::span<const uint8_t> forceMovable) {
  std::vector<BvhInstance> out;
  for (size_t i = 0; i < instances.size(); ++i)
    out.push_back({instances[i].mesh, toMat4(instances[i].worldFromObject),
                   instances[i].movable || (i < forceMovable.size() && forceMovable[i])});
  return out;
}

void worldBounds(const PackedScene& packed, std::span<const InstanceDesc> instances, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(1e30f);
  hi = glm::vec3(-1e30f);
  for (const InstanceDesc& inst : instances) {
    const glm::mat4 world = toMat4(inst.worldFromObject);
    const uint32_t first = packed.meshFirstGeometry[inst.mesh];
    for (uint32_t id = first; id < first + packed.meshGeometryCount[inst.mesh]; ++id)
      for (uint32_t v = 0; v < packed.geometryVertexCount[id]; ++v) {
        glm::vec3 p = glm::vec3(world * glm::vec4(packed.positions[packed.geometries[id].vertexOffset + v], 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
  }
}

float typicalRadiance(const PackedScene& packed, std::span<const LightDesc> lights, const SkyDesc& sky, float extent) {
  // A grey (0.5) surface a quarter of the scene away from the brightest
  // punctual light, a tenth of the brightest emission, or half the sky's
  // mean: only the order of magnitude matters.
  float typical = 0.0f;
  const float quarter = 0.25f * extent;
  for (const LightDesc& l : lights)
    typical = std::max(typical, gi::luminance(l.intensity[0], l.intensity[1], l.intensity[2]) / (quarter * quarter) *
                                    0.5f / std::numbers::pi_v<float>);
  for (const glm::vec3& e : packed.materialEmission) typical = std::max(typical, 0.1f * luminance(e));
  typical = std::max(typical,
                     0.5f * gi::luminance(sky.radiance[0], sky.radiance[1], sky.radiance[2]) * packed.skyMeanLuminance);
  return typical > 0.0f && std::isfinite(typical) ? typical : 1.0f;
}

}  // namespace gi
