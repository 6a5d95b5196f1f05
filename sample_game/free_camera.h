// The demo's camera: a free-flying camera (mouse look, WASD) and the scripted
// walkthrough, both producing an engine::Camera for the frame.
#pragma once
#include <glm/glm.hpp>

#include "scene.h"

namespace demo {

struct FreeCamera {
  glm::vec3 position{0.0f};
  float yaw = 0.0f;     // radians about +Y; 0 looks down −Z
  float pitch = 0.0f;   // radians, clamped to ±1.5
  float yfov = 1.0f;    // radians
  float znear = 0.05f;  // metres
};

struct CameraInput {
  glm::vec3 move{0.0f};      // right, up, back in [−1, 1] (WASD, Q/E)
  glm::vec2 look{0.0f};      // mouse motion in pixels while looking
  float speed = 1.0f;        // metres per second
  float lookScale = 0.003f;  // radians per pixel
};

FreeCamera freeCameraFrom(const engine::Camera& camera);
engine::Camera toCamera(const FreeCamera& camera);
void updateFreeCamera(FreeCamera& camera, const CameraInput& input, float seconds);

// The walkthrough: a closed, smooth loop around the start camera's position,
// looking at a point that sways across the view, scaled by the scene extent.
// Periodic in `loopSeconds`.
struct Walkthrough {
  FreeCamera start;
  float extent = 1.0f;  // metres
  float loopSeconds = 12.0f;
};
FreeCamera walkthroughCamera(const Walkthrough& path, float seconds);

}  // namespace demo
