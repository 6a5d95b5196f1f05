// Shared set-up for tests that drive the GI module: a pixel-centre reference
// (what the raster G-buffer sees) and a module session that fails the test
// when it cannot be created.
#pragma once
#include <cstring>
#include <functional>

#include "animation.h"
#include "gpu_test.h"
#include "module_session.h"

inline engine::ReferenceImages pixelCentreReference(const engine::Context& ctx, const LoadedScene& s,
                                                    const gpu::GpuCamera& cam, uint32_t bounces, uint32_t spp) {
  engine::ReferenceSettings settings;
  settings.maxBounces = bounces;
  settings.pixelJitter = false;  // the module sees the raster G-buffer: pixel centres
  return referenceOrFail(ctx, s.gpu, cam, settings, spp, 256).images;
}

// Use as ASSERT_NO_FATAL_FAILURE(openSession(...)).
inline void openSession(const engine::Context& ctx, const LoadedScene& s, VkExtent2D size, const gi::Settings& settings,
                        tools::ModuleSession& session, const gi::ModuleDesc* desc = nullptr) {
  std::string error;
  ASSERT_TRUE(tools::createModuleSession(ctx, s.gpu, size, settings, session, error, desc)) << error;
}

// The scene's camera moved sideways by `offset` metres along its own x axis.
inline engine::Camera panned(const engine::Camera& camera, float offset) {
  engine::Camera c = camera;
  c.worldFromView[3] += c.worldFromView[0] * offset;
  return c;
}

// Renders `frames` frames while the camera pans towards the scene's own
// camera (reaching it on the last frame, `step` metres a frame), and returns
// the last frame's images.
inline engine::ReferenceImages renderPan(const engine::Context& ctx, const LoadedScene& s, VkExtent2D size,
                                         const gi::Settings& settings, uint32_t frames, float step) {
  ScopedSession session(ctx);
  EXPECT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session));
  gpu::GpuCamera previous{};
  for (uint32_t i = 0; i < frames; ++i) {
    const engine::Camera c = panned(s.scene.cameras[0], float(frames - 1 - i) * step);
    const gpu::GpuCamera cam = engine::makeGpuCamera(c, size.width, size.height, i > 0 ? &previous : nullptr);
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, i > 0 ? previous : cam, i);
    previous = cam;
  }
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  tools::destroyModuleSession(ctx, session);
  return out;
}

// `frames` frames of `settings` at size × size from the scene's camera, the
// last frame's outputs. With `moving`, the light circles and a block turns
// (30 frames a second from the animation's start: the animation is made once,
// from the scene as loaded); without, the scene stays at that start.
// `afterFrame` runs after each frame has completed.
inline engine::ReferenceImages renderAnimatedFrames(const engine::Context& ctx, LoadedScene& s,
                                                    const engine::SceneAnimation& animation,
                                                    const gi::Settings& settings, uint32_t size, uint32_t frames,
                                                    bool moving,
                                                    const std::function<void(tools::ModuleSession&)>& afterFrame = {},
                                                    const gi::ModuleDesc* desc = nullptr) {
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size, size, nullptr);
  ScopedSession session(ctx);
  EXPECT_NO_FATAL_FAILURE(openSession(ctx, s, {size, size}, settings, session, desc));
  if (!session.module) return {};
  for (uint32_t f = 0; f < frames; ++f) {
    // Frame 0 jumps to the start: no motion from whatever pose the last run left.
    if (f == 0)
      jumpOrFail(ctx, animation, 0.0f, s.scene, s.gpu);
    else if (moving)
      poseOrFail(ctx, animation, float(f) / 30.0f, s.scene, s.gpu);
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    if (afterFrame) afterFrame(session);
  }
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  tools::destroyModuleSession(ctx, session);
  return out;
}

// The direct output of `frames` frames of raw at size × size (direct light only: its indirect is apart),
// still camera; with `accumulate`, their running mean.
inline engine::FloatImage rawDirectAfter(const engine::Context& ctx, LoadedScene& s, gi::Settings settings,
                                         uint32_t size, uint32_t frames, bool accumulate) {
  settings.method = gi::Method::Raw;
  settings.raw.temporalAccumulation = accumulate;
  settings.raw.temporalReprojection = false;
  settings.raw.maxAccumulatedFrames = frames;
  const engine::SceneAnimation still = engine::makeSceneAnimation(s.scene);
  return renderAnimatedFrames(ctx, s, still, settings, size, frames, false).direct;
}

inline bool sameBits(const engine::FloatImage& a, const engine::FloatImage& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}
