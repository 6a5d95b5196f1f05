#include "camera.h"

#include <cmath>
#include <cstring>

namespace engine {

gpu::GpuCamera makeGpuCamera(const Camera& camera, uint32_t width, uint32_t height, const gpu::GpuCamera* previous,
                             glm::vec2 ndcShift) {
  gpu::GpuCamera c{};
  c.worldFromView = camera.worldFromView;
  c.viewFromWorld = glm::inverse(camera.worldFromView);
  c.aspect = float(width) / float(height);
  c.tanHalfFovY = std::tan(0.5f * camera.yfov);
  c.imageSize = glm::vec2(float(width), float(height));
  c.position = glm::vec3(camera.worldFromView[3]);
  // Reversed Z, y down: depth 1 at znear, 0 at zfar (or infinity). With a
  // float depth buffer this keeps precision from millimetres to 1e5 m; the
  // plain mapping (0 at znear) rounds every depth past ~1e4·znear to 1 and
  // loses whole scenes.
  float n = camera.znear;
  glm::mat4 proj(0.0f);
  proj[0][0] = 1.0f / (c.aspect * c.tanHalfFovY);
  proj[1][1] = -1.0f / c.tanHalfFovY;
  proj[2][3] = -1.0f;
  proj[2][0] = -ndcShift.x;  // clip w = −z_view: ndc' = ndc + shift
  proj[2][1] = -ndcShift.y;
  if (camera.zfar > n) {
    float f = camera.zfar;
    proj[2][2] = n / (f - n);
    proj[3][2] = n * f / (f - n);
  } else {
    proj[2][2] = 0.0f;
    proj[3][2] = n;
  }
  c.clipFromWorld = proj * c.viewFromWorld;
  c.ndcShift = ndcShift;
  c.previousClipFromWorld = previous ? previous->clipFromWorld : c.clipFromWorld;
  return c;
}

gi::CameraDesc moduleCamera(const gpu::GpuCamera& c) {
  gi::CameraDesc d;
  const glm::mat4 clipFromView = c.clipFromWorld * c.worldFromView;
  std::memcpy(d.viewFromWorld, &c.viewFromWorld, sizeof(d.viewFromWorld));
  std::memcpy(d.clipFromView, &clipFromView, sizeof(d.clipFromView));
  return d;
}

}  // namespace engine
