#include "camera.h"

#include <cmath>

namespace engine {

gpu::GpuCamera makeGpuCamera(const Camera& camera, uint32_t width, uint32_t height, const gpu::GpuCamera* previous) {
  gpu::GpuCamera c{};
  c.worldFromView = camera.worldFromView;
  c.viewFromWorld = glm::inverse(camera.worldFromView);
  c.aspect = float(width) / float(height);
  c.tanHalfFovY = std::tan(0.5f * camera.yfov);
  c.imageSize = glm::vec2(float(width), float(height));
  c.position = glm::vec3(camera.worldFromView[3]);
  // Reversed-nothing, plain Vulkan projection: depth 0 at znear, 1 at zfar (or infinity), y down.
  float n = camera.znear;
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f / (c.aspect * c.tanHalfFovY);
  proj[1][1] = -1.0f / c.tanHalfFovY;
  proj[2][3] = -1.0f;
  if (camera.zfar > n) {
    float f = camera.zfar;
    proj[2][2] = f / (n - f);
    proj[3][2] = n * f / (n - f);
  } else {
    proj[2][2] = -1.0f;
    proj[3][2] = -n;
  }
  c.clipFromWorld = proj * c.viewFromWorld;
  c.previousClipFromWorld = previous ? previous->clipFromWorld : c.clipFromWorld;
  return c;
}

}  // namespace engine
