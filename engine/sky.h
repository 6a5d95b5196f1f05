// The sky: light from beyond the scene, for rays that leave it. A constant
// radiance, or an equirectangular map (+Y up, −Z at the map's centre column;
// shared/gpu_scene.h) scaled by it. Black when its radiance is zero.
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "image_io.h"

namespace engine {

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

}  // namespace engine
