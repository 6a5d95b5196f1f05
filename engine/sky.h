// The sky: light from beyond the scene, for rays that leave it. A constant
// radiance, or an equirectangular map (+Y up, −Z at the map's centre column;
// shared/gpu_scene.h) scaled by it. Black when its radiance is zero.
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "image_io.h"

namespace engine {

// Rec. 709 luminance of linear rgb.
inline float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

struct Sky {
  glm::vec3 radiance{0.0f};  // W/(sr·m²); with a map, the map's scale
  FloatImage map;            // rgb, linear; empty: a constant sky
  std::string mapPath;       // where the map came from (for messages)

  bool hasMap() const { return map.width > 0 && map.height > 0; }
  bool enabled() const { return radiance.x > 0.0f || radiance.y > 0.0f || radiance.z > 0.0f; }
};

// `--sky` values: "R,G,B" (constant radiance, each finite and ≥ 0) or a path
// to an equirectangular .exr or .pfm map (every texel finite and ≥ 0; scale
// 1). False with a message naming the value or the file and the problem.
bool parseSky(const std::string& value, Sky& out, std::string& error);

// The map's sampling tables (sky.glsl): H cumulative row probabilities, then
// per row W cumulative column probabilities, each ending at 1; texels
// weighted by luminance × sin θ at the row's centre. `sum` gets Σ of the
// weights (0: the map is black).
std::vector<float> skyDistribution(const FloatImage& map, float& sum);

// Mean luminance of the map's texels (each texel alike, not by solid angle).
float meanLuminance(const FloatImage& map);

}  // namespace engine
