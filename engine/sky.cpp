#include "sky.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace engine {
namespace {

bool parseColour(const std::string& value, glm::vec3& out) {
  std::stringstream in(value);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 3 || part.empty()) return false;
    char* end = nullptr;
    out[n++] = std::strtof(part.c_str(), &end);
    if (*end != '\0') return false;
  }
  return n == 3;
}

}  // namespace

bool parseSky(const std::string& value, Sky& out, std::string& error) {
  Sky sky;
  if (value.find(',') != std::string::npos) {
    if (!parseColour(value, sky.radiance)) {
      error = "--sky " + value + ": expected R,G,B (three numbers, W/(sr·m²)) or a .exr/.pfm map";
      return false;
    }
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(sky.radiance[c]) || sky.radiance[c] < 0.0f) {
        error = "--sky " + value + ": every component must be finite and at least 0";
        return false;
      }
    out = sky;
    return true;
  }
  if (!readImage(value, sky.map, error)) {
    error = "--sky: " + error;
    return false;
  }
  if (sky.map.channels < 3) {
    error = "--sky: " + value + " has " + std::to_string(sky.map.channels) + " channel(s); an rgb map is needed";
    return false;
  }
  for (size_t i = 0; i < sky.map.pixels.size(); ++i) {
    float v = sky.map.pixels[i];
    if (!std::isfinite(v) || v < 0.0f) {
      size_t pixel = i / sky.map.channels;
      error = "--sky: " + value + " texel (" + std::to_string(pixel % sky.map.width) + ", " +
              std::to_string(pixel / sky.map.width) + ") holds " + std::to_string(v) +
              "; radiance must be finite and ≥ 0";
      return false;
    }
  }
  sky.radiance = glm::vec3(1.0f);
  sky.mapPath = value;
  out = std::move(sky);
  return true;
}

}  // namespace engine
