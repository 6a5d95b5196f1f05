// Hashed path space filtering through the module: what reaches the cells,
// the telemetry, and convergence over frames.
#include <cstdio>

#include "gpu_test.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "procedural_scene.h"

class HpsfTest : public GpuTest {};

// A floor whose left half has albedo (1, 0, 0) next to a grey wall lit by a
// white point light. The cells store the radiance arriving at the floor,
// never pre-multiplied by its albedo, so the red half's cells keep the green
// and blue light that a neighbour (and the composite, if the albedo changed)
// could use.
TEST_F(HpsfTest, ZeroAlbedoChannelLosesNothingANeighbourCouldUse) {
  testscene::Description d;
  d.quads.push_back({{{-1, 0, 1}, {0, 0, 1}, {0, 0, -1}, {-1, 0, -1}}, glm::vec3(1, 0, 0)});  // red floor half
  d.quads.push_back({{{0, 0, 1}, {1, 0, 1}, {1, 0, -1}, {0, 0, -1}}, glm::vec3(0.8f)});       // grey floor half
  d.quads.push_back({{{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, glm::vec3(0.8f)});   // grey back wall
  d.lights.push_back({{0, 1.5f, 0.5f}, glm::vec3(2.0f)});
  d.eye = {0, 1.2f, 2.2f};
  d.target = {0, 0, -0.3f};
  LoadedScene s;
  load(testscene::write(d, "hpsf_zero_albedo"), s);
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 32, 32, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  settings.hpsf.samplesPerPixel = 4;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {32, 32}, settings, session));
  for (uint32_t f = 0; f < 4; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  double redFloorGreen = 0.0, redFloorPixels = 0.0;
  for (uint32_t y = 0; y < 32; ++y)
    for (uint32_t x = 0; x < 32; ++x) {
      bool redFloor = out.albedo.at(x, y, 0) > 0.9f && out.albedo.at(x, y, 1) < 0.01f;
      if (!redFloor) continue;
      redFloorGreen += out.indirect.at(x, y, 1);
      redFloorPixels += 1.0;
      EXPECT_NEAR(out.indirect.at(x, y, 1), out.indirect.at(x, y, 2), 1e-4f);  // white light off grey: g = b
    }
  ASSERT_GT(redFloorPixels, 20.0);
  EXPECT_GT(redFloorGreen / redFloorPixels, 0.01) << "green light arriving at the red floor was lost";
  // The composite multiplies by the albedo only at the end: no green there.
  for (uint32_t y = 0; y < 32; ++y)
    for (uint32_t x = 0; x < 32; ++x)
      if (out.albedo.at(x, y, 1) < 0.01f && out.albedo.at(x, y, 0) > 0.9f) {
        EXPECT_EQ(out.final.at(x, y, 1), 0.0f);
      }
}

TEST_F(HpsfTest, TelemetryAndErrorOverFramesForBothEvictionPolicies) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 1024);
  for (gi::EvictionPolicy policy : {gi::EvictionPolicy::Strict, gi::EvictionPolicy::Aging}) {
    gi::Settings settings;
    settings.method = gi::Method::Hpsf;
    settings.maxBounces = 2;
    settings.hpsf.eviction = policy;
    settings.hpsf.filterWidth = 8.0f;  // at 32 × 32 the default 16-pixel cells would span half the image: all bias
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
    std::vector<double> errors;
    for (uint32_t f = 0; f < 16; ++f) {
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
      if (f == 0 || f == 15)
        errors.push_back(metrics::mse(tools::readModuleImages(ctx, session).indirect, ref.indirect));
    }
    gi::FrameStats st = gi::stats(session.module);
    EXPECT_EQ(st.hash.capacity, 1024u);  // the floor, 2^10: 32 × 32 / 4 is below it
    // Pixels share cells: 8-pixel cells hold the samples of many pixels (measured 145 cells for 992
    // samples with strict eviction, 204 with aging, which keeps cells no sample reached this frame),
    // and they cover the image: at least one per 8 × 8 pixels.
    EXPECT_LT(st.hash.occupied, st.hash.inserts / 3);
    EXPECT_GT(st.hash.occupied, W * H / (8 * 8));
    EXPECT_EQ(st.hash.failedInserts, 0u);
    EXPECT_GT(st.hash.inserts, W * H / 2);
    EXPECT_GE(st.hash.meanProbe, 1.0f);
    EXPECT_LE(st.hash.maxProbe, settings.hpsf.probeWindow);
    // Both policies keep the cells' history over the 16 frames (measured 0.19× frame 0's error with
    // strict eviction, 0.13× with aging; a history lost every frame would stay near 1×).
    EXPECT_LT(errors[1], 0.3 * errors[0]) << "sixteen frames of history";
  }
}

// gi::invalidate(All) drops the cache: the next frame starts from an empty
// map. LightsChanged keeps every cell (its key and probe; aging evicts it
// only once it goes stale), and restarts their means.
TEST_F(HpsfTest, InvalidateAllEmptiesTheCacheAndLightsChangedKeepsTheCells) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 24, 24, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {24, 24}, settings, session));
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  uint32_t firstFrameOccupancy = gi::stats(session.module).hash.occupied;
  // Jitter and stochastic LOD touch new cells every frame: with aging they pile up.
  for (uint32_t f = 1; f < 6; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  uint32_t before = gi::stats(session.module).hash.occupied;
  EXPECT_GT(before, firstFrameOccupancy);
  gi::invalidate(session.module, gi::Invalidate::LightsChanged);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 6);
  gi::FrameStats kept = gi::stats(session.module);
  EXPECT_GE(kept.hash.occupied, before) << "LightsChanged evicted cells";
  EXPECT_EQ(kept.hash.evicted, 0u);
  gi::invalidate(session.module, gi::Invalidate::All);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 7);
  gi::FrameStats emptied = gi::stats(session.module);
  EXPECT_LE(emptied.hash.occupied, firstFrameOccupancy + firstFrameOccupancy / 4);
  for (float v : tools::readModuleImages(ctx, session).final.pixels) ASSERT_TRUE(std::isfinite(v));
}

// Strict eviction (Meijer): two tables swap every frame, and a cell touched
// this frame carries everything its key held over. Without jitter the same
// pixels land in the same cells each frame, so after frame f every cell holds
// f + 1 times frame 0's samples and no cell is evicted. Aging's history
// grows too (until historyFrames).
TEST_F(HpsfTest, StrictEvictionAccumulatesWhileACellIsTouchedEveryFrame) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 24, H = 24;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  for (gi::EvictionPolicy policy : {gi::EvictionPolicy::Strict, gi::EvictionPolicy::Aging}) {
    gi::Settings settings;
    settings.method = gi::Method::Hpsf;
    settings.hpsf.eviction = policy;
    settings.hpsf.jitter = 0.0f;
    settings.hpsf.stochasticLod = false;
    settings.debugView = gi::DebugView::HashSamples;  // samples behind the pixel's cell / 100
    // Single-float outputs: the counts are compared exactly (a half float holds 0.99 to 5e-4).
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {W, H});
    desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session, &desc));
    std::vector<engine::FloatImage> samples;
    std::vector<gi::FrameStats> stats;
    for (uint32_t f = 0; f < 4; ++f) {
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
      samples.push_back(tools::readModuleImages(ctx, session).final);
      stats.push_back(gi::stats(session.module));
    }
    bool strict = policy == gi::EvictionPolicy::Strict;
    size_t cells = 0, grew = 0;
    for (size_t i = 0; i < samples[0].pixels.size(); i += 3) {
      float first = samples[0].pixels[i];
      if (first <= 0.0f) continue;
      ++cells;
      for (uint32_t f = 1; strict && f < 4; ++f) {
        ASSERT_FLOAT_EQ(samples[f].pixels[i], float(f + 1) * first) << "pixel " << i / 3 << " frame " << f;
      }
      grew += samples[3].pixels[i] > 2.0f * first;
    }
    ASSERT_GT(cells, size_t(W * H / 2));
    EXPECT_EQ(grew, cells) << gi::methodName(settings.method) << (strict ? " strict" : " aging")
                           << " keeps more than two frames";
    if (strict) {
      for (uint32_t f = 1; f < 4; ++f) {
        EXPECT_EQ(stats[f].hash.occupied, stats[0].hash.occupied);
        EXPECT_EQ(stats[f].hash.evicted, 0u);
      }
    }
  }
}

// With jitter the cells move every frame: strict eviction drops the last
// frame's cells that nobody found again, so the map holds one frame's cells.
TEST_F(HpsfTest, StrictEvictionDropsCellsNotFoundAgain) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 24, 24, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  settings.hpsf.eviction = gi::EvictionPolicy::Strict;
  settings.debugView = gi::DebugView::HashOccupancy;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {24, 24}, settings, session));
  uint32_t evicted = 0;
  for (uint32_t f = 0; f < 6; ++f) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    gi::FrameStats st = gi::stats(session.module);
    EXPECT_LE(st.hash.occupied, st.hash.inserts) << "only cells inserted this frame live";
    if (f > 0) evicted += st.hash.evicted;
  }
  EXPECT_GT(evicted, 0u);
  // The occupancy view: a probe window's share of used slots, green (0) to red (1), on covered pixels.
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  size_t coloured = 0;
  for (size_t i = 0; i < out.final.pixels.size(); i += 3) {
    float r = out.final.pixels[i], g = out.final.pixels[i + 1];
    ASSERT_GE(r, 0.0f);
    ASSERT_LE(r, 1.0f);
    if (r + g > 0.0f) {
      EXPECT_NEAR(r + g, 1.0f, 1e-6f);
      ++coloured;
    }
  }
  EXPECT_GT(coloured, out.final.pixels.size() / 6);
}

// Strict eviction under the default jitter, still camera, 48 frames: the
// error falls smoothly, no frame above 1.3× the mean of its two neighbours.
// Before the lookup looked past cells younger than the outlier clamp, a
// pixel whose jitter reached a cell alone (a sliver, or a cell that no pixel
// reached last frame and so started over) showed its one path as it came:
// single pixels near the light with 0.5 of squared error, frames at 2.6×
// their neighbours' error (64 × 48, Cornell).
TEST_F(HpsfTest, StrictEvictionConvergesWithoutSpikes) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 64, H = 48, kFrames = 48;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  settings.maxBounces = 2;
  settings.hpsf.eviction = gi::EvictionPolicy::Strict;
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, settings.maxBounces, 1024);
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  std::vector<double> errors;
  for (uint32_t f = 0; f < kFrames; ++f) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    errors.push_back(metrics::mse(tools::readModuleImages(ctx, session).indirect, ref.indirect));
  }
  double worst = 0.0;
  uint32_t worstFrame = 0;
  for (uint32_t f = 1; f + 1 < kFrames; ++f) {
    const double ratio = errors[f] / (0.5 * (errors[f - 1] + errors[f + 1]));
    if (ratio > worst) worst = ratio, worstFrame = f;
  }
  std::printf("strict eviction: worst frame %u at %.2fx its neighbours' mean; error frame 0 %.3e, last %.3e\n",
              worstFrame, worst, errors.front(), errors.back());
  EXPECT_LT(worst, 1.3) << "frame " << worstFrame;
  EXPECT_LT(errors.back(), 0.3 * errors.front()) << "the history still accumulates";
}
