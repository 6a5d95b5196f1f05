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
              std::to_string(pixel / sky.map.width) + ") holds " + std::to_string(v) + "; radiance must be finite and ≥ 0";
      return false;
    }
  }
  sky.radiance = glm::vec3(1.0f);
  sky.mapPath = value;
  out = std::move(sky);
  return true;
}

std::vector<float> skyDistribution(const FloatImage& map, float& sum) {
  const uint32_t w = map.width, h = map.height;
  std::vector<float> tables(size_t(h) + size_t(w) * h, 0.0f);
  std::vector<double> rowSums(h, 0.0);
  double total = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    const double sinTheta = std::sin(3.14159265358979 * (y + 0.5) / h);
    float* row = &tables[h + size_t(y) * w];
    double running = 0.0;
    for (uint32_t x = 0; x < w; ++x) {
      running += luminance({map.at(x, y, 0), map.at(x, y, 1), map.at(x, y, 2)}) * sinTheta;
      row[x] = float(running);
    }
    // A black row: uniform (its probability is 0 anyway).
    for (uint32_t x = 0; x < w; ++x) row[x] = running > 0.0 ? float(row[x] / running) : float(x + 1) / float(w);
    row[w - 1] = 1.0f;
    rowSums[y] = running;
    total += running;
  }
  double running = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    running += rowSums[y];
    tables[y] = total > 0.0 ? float(running / total) : float(y + 1) / float(h);
  }
  if (h > 0) tables[h - 1] = 1.0f;
  sum = float(total);
  return tables;
}

float meanLuminance(const FloatImage& map) {
  double sum = 0.0;
  for (uint32_t y = 0; y < map.height; ++y)
    for (uint32_t x = 0; x < map.width; ++x) sum += luminance({map.at(x, y, 0), map.at(x, y, 1), map.at(x, y, 2)});
  return map.width && map.height ? float(sum / (double(map.width) * map.height)) : 0.0f;
}

}  // namespace engine
