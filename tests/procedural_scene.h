// Small glTF scenes written by the tests themselves: quads with materials,
// point and spot lights and one camera. Each test builds only the scene it needs.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <unistd.h>  // getpid

namespace testscene {

struct Quad {
  glm::vec3 corner[4];  // counter-clockwise seen from the side the normal points to
  glm::vec3 albedo{0.5f};
  glm::vec3 emission{0.0f};
  float roughness = 1.0f;  // below 0.9 (or metallic > 0) the material gets a GGX lobe
  float metallic = 0.0f;
};

struct Light {
  glm::vec3 position;
  glm::vec3 intensity;      // W/sr
  float outerCone = 0.0f;   // radians: a spot with this outer and half of it as inner cone angle; 0: a point light
  glm::vec3 aim{0, -1, 0};  // a spot's direction (unit)
};

struct Description {
  std::vector<Quad> quads;
  std::vector<Light> lights;
  glm::vec3 eye{0, 1, 3}, target{0, 0, 0};
  float yfov = 0.8f;
  float znear = 0.01f;  // metres
};

inline std::string base64(const std::vector<uint8_t>& data) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = uint32_t(data[i]) << 16 | (i + 1 < data.size() ? uint32_t(data[i + 1]) << 8 : 0) |
                 (i + 2 < data.size() ? data[i + 2] : 0);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? table[v & 63] : '=';
  }
  return out;
}

// Writes DIR/NAME.gltf (buffers embedded) and returns its path.
inline std::string write(const Description& d, const std::string& name) {
  std::vector<uint8_t> bin;
  auto put = [&](const void* p, size_t n) {
    size_t at = bin.size();
    bin.resize(at + n);
    std::memcpy(&bin[at], p, n);
    return at;
  };
  nlohmann::json j;
  j["asset"] = {{"version", "2.0"}};
  j["scene"] = 0;
  nlohmann::json nodes = nlohmann::json::array(), meshes = nlohmann::json::array(), materials = nlohmann::json::array(),
                 accessors = nlohmann::json::array(), views = nlohmann::json::array();
  for (const Quad& q : d.quads) {
    glm::vec3 across = glm::cross(q.corner[1] - q.corner[0], q.corner[2] - q.corner[0]);
    glm::vec3 n = glm::dot(across, across) > 0.0f ? glm::normalize(across)
                                                  : glm::vec3(0, 1, 0);  // zero-area quads still get a normal
    float pos[12], nrm[12];
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) {
        pos[3 * k + c] = q.corner[k][c];
        nrm[3 * k + c] = n[c];
      }
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    size_t pAt = put(pos, sizeof(pos)), nAt = put(nrm, sizeof(nrm)), iAt = put(idx, sizeof(idx));
    size_t v0 = views.size();
    views.push_back({{"buffer", 0}, {"byteOffset", pAt}, {"byteLength", sizeof(pos)}});
    views.push_back({{"buffer", 0}, {"byteOffset", nAt}, {"byteLength", sizeof(nrm)}});
    views.push_back({{"buffer", 0}, {"byteOffset", iAt}, {"byteLength", sizeof(idx)}});
    size_t a0 = accessors.size();
    accessors.push_back({{"bufferView", v0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
    accessors.push_back({{"bufferView", v0 + 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
    accessors.push_back({{"bufferView", v0 + 2}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}});
    nlohmann::json mat = {{"pbrMetallicRoughness",
                           {{"baseColorFactor", {q.albedo.x, q.albedo.y, q.albedo.z, 1.0}},
                            {"metallicFactor", q.metallic},
                            {"roughnessFactor", q.roughness}}}};
    float e = std::max(q.emission.x, std::max(q.emission.y, q.emission.z));
    if (e > 0.0f) {
      mat["emissiveFactor"] = {q.emission.x / e, q.emission.y / e, q.emission.z / e};
      mat["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", e}}}};
    }
    materials.push_back(mat);
    meshes.push_back({{"primitives",
                       {{{"attributes", {{"POSITION", a0}, {"NORMAL", a0 + 1}}},
                         {"indices", a0 + 2},
                         {"material", materials.size() - 1}}}}});
    nodes.push_back({{"mesh", meshes.size() - 1}});
  }
  nlohmann::json lights = nlohmann::json::array();
  for (const Light& l : d.lights) {
    float i = std::max(l.intensity.x, std::max(l.intensity.y, l.intensity.z));
    nlohmann::json light = {{"color", {l.intensity.x / i, l.intensity.y / i, l.intensity.z / i}}, {"intensity", i}};
    // A spot shines down its node's −Z: the rotation that turns −Z to `aim`.
    const glm::quat turn(glm::vec3(0, 0, -1), glm::normalize(l.aim));
    if (l.outerCone > 0.0f) {
      light["type"] = "spot";
      light["spot"] = {{"innerConeAngle", 0.5f * l.outerCone}, {"outerConeAngle", l.outerCone}};
    } else {
      light["type"] = "point";
    }
    lights.push_back(light);
    nodes.push_back({{"translation", {l.position.x, l.position.y, l.position.z}},
                     {"rotation", {turn.x, turn.y, turn.z, turn.w}},
                     {"extensions", {{"KHR_lights_punctual", {{"light", lights.size() - 1}}}}}});
  }
  // Camera: look from eye to target (view −Z), Y up.
  glm::vec3 f = glm::normalize(d.target - d.eye);
  glm::vec3 up = std::abs(f.y) > 0.99f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  glm::vec3 r = glm::normalize(glm::cross(f, up)), u = glm::cross(r, f);
  glm::quat q = glm::quat_cast(glm::mat3(r, u, -f));
  nodes.push_back({{"camera", 0}, {"translation", {d.eye.x, d.eye.y, d.eye.z}}, {"rotation", {q.x, q.y, q.z, q.w}}});
  j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", d.yfov}, {"znear", d.znear}}}}};
  nlohmann::json roots = nlohmann::json::array();
  for (size_t i = 0; i < nodes.size(); ++i) roots.push_back(i);
  j["scenes"] = {{{"nodes", roots}}};
  j["nodes"] = nodes;
  if (!meshes.empty()) {
    j["meshes"] = meshes;
    j["materials"] = materials;
    j["accessors"] = accessors;
    j["bufferViews"] = views;
    j["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
  }
  if (!lights.empty()) {
    j["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};
    j["extensions"] = {{"KHR_lights_punctual", {{"lights", lights}}}};
  }
  // Written beside the path and renamed onto it (atomic on one file system): ctest runs tests in parallel
  // processes, and two that write the same scene must never let a third read it half written (a load of
  // an emptied file failed that way when two EmissiveSamplerTest cases started together).
  const std::filesystem::path path = std::filesystem::temp_directory_path() / (name + ".gltf");
  const std::filesystem::path written = path.string().append(".").append(std::to_string(getpid())).append(".part");
  {
    std::ofstream out(written);
    out << j.dump(1);
  }
  std::error_code error;
  std::filesystem::rename(written, path, error);  // on failure the load names the file and what is wrong
  if (error) std::filesystem::remove(written, error);
  return path.string();
}

}  // namespace testscene
