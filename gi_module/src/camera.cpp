// The engine's camera (gi::CameraDesc: plain column-major matrices) as the
// module's passes see it (gpu::GpuCamera).
#include <cmath>
#include <cstring>
#include <string>

#include "module.h"

namespace gi {
namespace {

glm::mat4 toMat4(const float (&m)[16]) {
  glm::mat4 out;
  std::memcpy(&out, m, sizeof(out));
  return out;
}

// The projection with NDC y down the image (Vulkan's standard viewport). A
// positive P[1][1] means y up in clip space and a viewport of negative
// height: negating the second row gives the same image with y down.
glm::mat4 projectionYDown(const float (&m)[16]) {
  glm::mat4 p = toMat4(m);
  if (p[1][1] > 0.0f)
    for (int c = 0; c < 4; ++c) p[c][1] = -p[c][1];
  return p;
}

bool finite(const float (&m)[16]) {
  for (float v : m)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

Error checkCamera(const CameraDesc& c, const char* what) {
  if (!finite(c.viewFromWorld) || !finite(c.clipFromView))
    return {ErrorCode::OutOfRange, std::string("gi::recordFrame: ") + what + " holds a value that is not finite"};
  const glm::mat4 view = toMat4(c.viewFromWorld), proj = toMat4(c.clipFromView);
  if (!(std::fabs(glm::determinant(glm::mat3(view))) > 1e-12f))
    return {ErrorCode::OutOfRange, std::string("gi::recordFrame: ") + what + ".viewFromWorld is not invertible"};
  // A perspective projection: clip w = −z_view (to rounding: engines may hand
  // over clipFromWorld × worldFromView).
  constexpr float kTolerance = 1e-4f;
  if (std::fabs(proj[0][3]) > kTolerance || std::fabs(proj[1][3]) > kTolerance ||
      std::fabs(proj[2][3] + 1.0f) > kTolerance || std::fabs(proj[3][3]) > kTolerance || proj[0][0] == 0.0f ||
      proj[1][1] == 0.0f)
    return {ErrorCode::OutOfRange, std::string("gi::recordFrame: ") + what +
                                       ".clipFromView is not a perspective projection with clip w = −z_view"};
  return {};
}

glm::mat4 clipFromView(const CameraDesc& c) { return projectionYDown(c.clipFromView); }

gpu::GpuCamera gpuCamera(const CameraDesc& now, const CameraDesc& previous, uint32_t width, uint32_t height) {
  gpu::GpuCamera c{};
  const glm::mat4 proj = clipFromView(now);
  c.viewFromWorld = toMat4(now.viewFromWorld);
  c.worldFromView = glm::inverse(c.viewFromWorld);
  c.clipFromWorld = proj * c.viewFromWorld;
  c.previousClipFromWorld = projectionYDown(previous.clipFromView) * toMat4(previous.viewFromWorld);
  c.position = glm::vec3(c.worldFromView[3]);
  // x_ndc = −(P00·x + P20·z)/z for a view point (x, y, z): a symmetric frustum
  // of these half-angles, shifted by (−P20, −P21) in NDC (jitter, off-axis).
  c.tanHalfFovY = 1.0f / std::fabs(proj[1][1]);
  c.aspect = std::fabs(proj[1][1]) / std::fabs(proj[0][0]);
  c.imageSize = glm::vec2(float(width), float(height));
  c.ndcShift = glm::vec2(-proj[2][0], -proj[2][1]);
  return c;
}

}  // namespace gi
