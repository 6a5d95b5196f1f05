// Temporal reprojection (gi_temporal.comp, <method>.temporalReprojection): under a
// camera pan the reprojected history lowers the error about as 1/frames, and
// pixels the pan uncovers start over with this frame's light only.
#include "metrics.h"
#include "module_test_helpers.h"

class TemporalTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 48;

}  // namespace

// With the camera panning a quarter pixel a frame, the last frame's error
// against a converged reference falls as the history grows (1/(frames+1)
// blending, down to temporal.minBlend = 0.1, about 19 frames' worth);
// without reprojection every frame is one sample again.
TEST_F(TemporalTest, ReprojectedHistoryLowersTheErrorAsItGrows) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  const gpu::GpuCamera finalCamera = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceImages reference = pixelCentreReference(ctx, s, finalCamera, 1, 1024);
  const float step = 0.01f;  // metres a frame: about a sixth of a pixel on the back wall
  gi::Settings settings;
  settings.method = gi::Method::Raw;
  double indirect[2][3], direct[2][3];
  const uint32_t frames[3] = {1, 4, 16};
  for (int on = 0; on < 2; ++on) {
    settings.raw.temporalReprojection = on == 1;
    for (int k = 0; k < 3; ++k) {
      const engine::ReferenceImages img = renderPan(ctx, s, {kSize, kSize}, settings, frames[k], step);
      indirect[on][k] = metrics::mse(img.indirect, reference.indirect);
      direct[on][k] = metrics::mse(img.direct, reference.direct);
      std::printf("temporal %s, %2u frames: indirect MSE %.3e, direct MSE %.3e\n", on ? "on " : "off", frames[k],
                  indirect[on][k], direct[on][k]);
    }
  }
  // Reprojected history: 4 frames at most half the error of one, 16 at most a quarter.
  EXPECT_LT(indirect[1][1], 0.5 * indirect[1][0]);
  EXPECT_LT(indirect[1][2], 0.25 * indirect[1][0]);
  EXPECT_LT(direct[1][1], 0.5 * direct[1][0]);
  EXPECT_LT(direct[1][2], 0.25 * direct[1][0]);
  // Without it the pan leaves every frame on its own.
  EXPECT_GT(indirect[0][2], 0.7 * indirect[0][0]);
  // The hash methods reproject their direct light (hpsf.temporal, the default): the map caches the
  // indirect, which is left as it is, or with hpsf.temporalIndirect held near the pixels' own
  // accumulated samples (the filter clamp).
  gi::Settings hpsf;
  hpsf.method = gi::Method::Hpsf;
  double hpsfDirect[3], hpsfIndirect[3];
  for (int run = 0; run < 3; ++run) {  // hpsf.temporal off; on (the default); on with temporalIndirect
    hpsf.hpsf.temporalDirect = run > 0;
    hpsf.hpsf.temporalIndirect = run == 2;
    const engine::ReferenceImages img = renderPan(ctx, s, {kSize, kSize}, hpsf, 16, step);
    hpsfDirect[run] = metrics::mse(img.direct, reference.direct);
    hpsfIndirect[run] = metrics::mse(img.indirect, reference.indirect);
    std::printf("hpsf, hpsf.temporal %s, 16 frames: indirect MSE %.3e, direct MSE %.3e\n",
                run == 0   ? "off"
                : run == 1 ? "on"
                           : "on, own indirect too",
                hpsfIndirect[run], hpsfDirect[run]);
  }
  EXPECT_LT(hpsfDirect[1], 0.25 * hpsfDirect[0]);
  EXPECT_LT(hpsfDirect[2], 0.25 * hpsfDirect[0]);
  EXPECT_EQ(hpsfIndirect[1], hpsfIndirect[0]) << "without the clamp the map's indirect light is left as it is";
  // Alone, the direct history is the packed image (RGB9E5 light, 9 bits of mantissa); with the
  // pixels' own indirect samples it is the fp32 images the screen methods use: the same light, to
  // the packing's rounding (measured 48², pan: direct MSE 1.306e-5 packed, 1.309e-5 in fp32).
  EXPECT_NEAR(hpsfDirect[2], hpsfDirect[1], 0.05 * hpsfDirect[1])
      << "the clamp holds the map's light, not the direct light";
  // Measured (48², pan): 4.19e-5 against 8.77e-5 unclamped.
  EXPECT_LT(hpsfIndirect[2], 0.75 * hpsfIndirect[1]) << "held near the pixels' own samples";
}

// Eight still frames, then the camera jumps sideways by 30 cm (about five
// pixels on the back wall). Pixels whose history is gone (what came into
// view, and surfaces the blocks hid) hold exactly what a module without
// history shows for that frame: no stale colour. Most others keep theirs.
TEST_F(TemporalTest, DisoccludedPixelsStartOver) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  const engine::Camera before = panned(s.scene.cameras[0], -0.15f), after = panned(s.scene.cameras[0], 0.15f);
  gi::Settings settings;
  settings.method = gi::Method::Raw;
  settings.raw.temporalReprojection = true;
  auto run = [&](const gi::Settings& st, bool stillFrames) {
    ScopedSession session(ctx);
    EXPECT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, st, session));
    const gpu::GpuCamera a = engine::makeGpuCamera(before, kSize, kSize, nullptr);
    if (stillFrames)
      for (uint32_t i = 0; i < 8; ++i) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, a, a, i);
    const gpu::GpuCamera b = engine::makeGpuCamera(after, kSize, kSize, &a);
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, b, a, 8);
    engine::ReferenceImages out = tools::readModuleImages(ctx, session);
    tools::destroyModuleSession(ctx, session);
    return out;
  };
  const engine::ReferenceImages temporal = run(settings, true);
  gi::Settings history = settings;
  history.debugView = gi::DebugView::TemporalHistory;
  const engine::ReferenceImages frames = run(history, true);
  gi::Settings none = settings;
  none.raw.temporalReprojection = false;
  const engine::ReferenceImages fresh = run(none, false);

  // Where each covered pixel's surface was in the frame before the jump: off
  // screen means it came into view.
  const gpu::GpuCamera a = engine::makeGpuCamera(before, kSize, kSize, nullptr);
  const gpu::GpuCamera b = engine::makeGpuCamera(after, kSize, kSize, &a);
  auto cameInToView = [&](uint32_t x, uint32_t y, float viewDepth) {
    const glm::vec3 dir = gpu::giCameraRayDirection(b, glm::vec2(x + 0.5f, y + 0.5f));
    const glm::vec3 forward = -glm::vec3(b.worldFromView[2]);
    const glm::vec3 world = b.position + dir * (viewDepth / glm::dot(dir, forward));
    const glm::vec4 clip = a.clipFromWorld * glm::vec4(world, 1.0f);
    const glm::vec2 pixel = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * float(kSize);
    return pixel.x < -1.0f || pixel.y < -1.0f || pixel.x > kSize + 1.0f || pixel.y > kSize + 1.0f;
  };
  size_t covered = 0, restarted = 0, cameIn = 0, cameInKept = 0, stale = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const size_t p = size_t(y) * kSize + x;
      if (!(fresh.depth.pixels[p] > 0.0f)) continue;
      covered++;
      const bool fromOutside = cameInToView(x, y, fresh.depth.pixels[p]);
      const float historyFrames = frames.final.pixels[3 * p] * 32.0f;
      cameIn += fromOutside;
      if (historyFrames > 1.5f) {
        cameInKept += fromOutside;
        continue;
      }
      restarted++;
      for (int c = 0; c < 3; ++c)
        stale += temporal.indirect.pixels[3 * p + c] != fresh.indirect.pixels[3 * p + c] ||
                 temporal.direct.pixels[3 * p + c] != fresh.direct.pixels[3 * p + c];
    }
  std::printf(
      "%zu covered pixels: %zu started over, %zu came into view (%zu of them kept a history), %zu values differ "
      "from a fresh frame\n",
      covered, restarted, cameIn, cameInKept, stale);
  EXPECT_EQ(stale, 0u) << "a pixel without history shows only this frame's light";
  EXPECT_GT(cameIn, size_t(kSize)) << "the jump should bring a strip into view";
  EXPECT_EQ(cameInKept, 0u) << "what came into view has no history";
  EXPECT_GT(restarted, cameIn) << "surfaces the blocks hid start over too";
  EXPECT_LT(restarted, covered / 3) << "most of the picture keeps its history";
}
