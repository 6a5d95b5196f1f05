#include "free_camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace demo {
namespace {

glm::mat3 orientation(float yaw, float pitch) {
  glm::mat4 m =
      glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)) * glm::rotate(glm::mat4(1.0f), pitch, glm::vec3(1, 0, 0));
  return glm::mat3(m);
}

}  // namespace

FreeCamera freeCameraFrom(const engine::Camera& c) {
  FreeCamera f;
  f.position = glm::vec3(c.worldFromView[3]);
  glm::vec3 forward = -glm::normalize(glm::vec3(c.worldFromView[2]));
  f.yaw = std::atan2(-forward.x, -forward.z);
  f.pitch = std::asin(std::clamp(forward.y, -1.0f, 1.0f));
  f.yfov = c.yfov;
  f.znear = c.znear;
  return f;
}

engine::Camera toCamera(const FreeCamera& f) {
  engine::Camera c;
  c.name = "free";
  glm::mat3 r = orientation(f.yaw, f.pitch);
  c.worldFromView = glm::mat4(r);
  c.worldFromView[3] = glm::vec4(f.position, 1.0f);
  c.yfov = f.yfov;
  c.znear = f.znear;
  return c;
}

void updateFreeCamera(FreeCamera& f, const CameraInput& in, float seconds) {
  f.yaw -= in.look.x * in.lookScale;
  f.pitch = std::clamp(f.pitch - in.look.y * in.lookScale, -1.5f, 1.5f);
  glm::mat3 r = orientation(f.yaw, f.pitch);
  f.position += r * in.move * (in.speed * seconds);
}

FreeCamera walkthroughCamera(const Walkthrough& w, float seconds) {
  const float phase = 6.2831853f * std::fmod(seconds / w.loopSeconds, 1.0f);
  FreeCamera f = w.start;
  // A figure-of-eight drift (10% of the extent sideways, 5% forward and up)
  // with the view swinging ±0.35 rad: the whole loop stays near the start view.
  glm::mat3 r = orientation(w.start.yaw, 0.0f);
  glm::vec3 offset(0.10f * w.extent * std::sin(phase), 0.03f * w.extent * std::sin(2.0f * phase),
                   -0.05f * w.extent * (1.0f - std::cos(phase)));
  f.position = w.start.position + r * offset;
  f.yaw = w.start.yaw + 0.35f * std::sin(phase + 0.6f);
  f.pitch = w.start.pitch + 0.05f * std::sin(2.0f * phase);
  return f;
}

}  // namespace demo
