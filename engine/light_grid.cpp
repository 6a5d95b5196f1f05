#include "light_grid.h"

#include <cmath>
#include <vector>

namespace engine {

bool spreadPointLights(Scene& scene, uint32_t count, std::string& error) {
  if (count == 0) {
    error = "a scene needs at least one point light: 0 asked for";
    return false;
  }
  glm::vec3 total{0.0f};
  double height = 0.0;
  std::vector<PunctualLight> kept;
  uint32_t points = 0;
  for (const PunctualLight& light : scene.lights) {
    if (light.type != LightType::Point) {
      kept.push_back(light);
      continue;
    }
    total += light.intensity;
    height += light.position.y;
    ++points;
  }
  if (points == 0) {
    error = scene.sourcePath + ": the scene has no point light to spread";
    return false;
  }
  height /= points;
  const Bounds bounds = scene.worldBounds();
  const glm::vec3 inset = 0.1f * (bounds.max - bounds.min);
  const glm::vec3 low = bounds.min + inset, high = bounds.max - inset;
  const uint32_t cols = uint32_t(std::ceil(std::sqrt(double(count))));
  const uint32_t rows = (count + cols - 1) / cols;
  for (uint32_t i = 0; i < count; ++i) {
    PunctualLight light;
    light.name = "grid " + std::to_string(i);
    light.type = LightType::Point;
    const float u = (float(i % cols) + 0.5f) / float(cols), v = (float(i / cols) + 0.5f) / float(rows);
    light.position = {low.x + u * (high.x - low.x), float(height), low.z + v * (high.z - low.z)};
    light.intensity = total / float(count);
    kept.push_back(light);
  }
  scene.lights = std::move(kept);
  return true;
}

}  // namespace engine
