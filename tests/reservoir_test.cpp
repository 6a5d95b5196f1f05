// gi::ReservoirSettings (shaders/gi_reservoirs.comp): the primary hits' point
// and spot lights resampled through reservoirs. Against the exact sum over
// every light (the same scene with the `all` sampler): the direct light keeps
// its expectation, a frame with temporal reuse is far closer to it than the
// light tree's one pick a vertex, neither reuse makes fireflies, and a scene
// whose NEE is exact runs no reservoir pass.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "light_field.h"
#include "module_test_helpers.h"

class ReservoirTest : public LightFieldTest {};

namespace {

constexpr uint32_t kSize = 48;

double mseOf(const engine::FloatImage& a, const engine::FloatImage& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += (double(a.pixels[i]) - b.pixels[i]) * (double(a.pixels[i]) - b.pixels[i]);
  return sum / double(a.pixels.size());
}

// The direct output of `frames` frames of raw (direct light only: its indirect is apart), still camera;
// with `accumulate`, their running mean.
engine::FloatImage directAfter(const engine::Context& ctx, LoadedScene& s, gi::Settings settings, uint32_t frames,
                               bool accumulate) {
  settings.method = gi::Method::Raw;
  settings.raw.temporalAccumulation = accumulate;
  settings.raw.temporalReprojection = false;
  settings.raw.maxAccumulatedFrames = frames;
  const engine::SceneAnimation still = engine::makeSceneAnimation(s.scene);
  return renderAnimatedFrames(ctx, s, still, settings, kSize, frames, false).direct;
}

}  // namespace

// 64 lights and the block (lightField), 64 frames of resampled direct light, averaged: with temporal reuse (1/M weights, the default) the exact
// sum's image in mean (within 1%) and in every 8×8 block (within 6%); with spatial reuse too (the balance
// heuristic) in mean (within 2%); one frame with temporal reuse, after 15 before it, under a third of the tree's error with one pick
// a vertex; and no pixel of any frame brighter than 4× the exact image's brightest (the biased spatial
// weights, measured on Conference, made pixels 10× the brightest).
TEST_F(ReservoirTest, ResampledDirectLightKeepsTheExactSumsExpectation) {
  const std::string path = lightField(64, "reservoir_field", true);
  LoadedScene exact, picked;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_ALL, exact));
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, picked));
  ASSERT_TRUE(picked.gpu.desc.picksPunctualLights);
  gi::Settings base;
  base.maxBounces = 1;
  const engine::FloatImage truth = directAfter(ctx, exact, base, 4, true);  // exact: no noise from the lights
  const float brightest = *std::max_element(truth.pixels.begin(), truth.pixels.end());
  ASSERT_GT(meanOf(truth), 0.0);

  gi::Settings temporal = base;
  temporal.reservoirs.enabled = true;
  temporal.reservoirs.neighbours = 0;
  gi::Settings spatial = temporal;
  spatial.reservoirs.neighbours = 3;
  spatial.reservoirs.radius = 4.0f;
  spatial.reservoirs.unbiased = true;
  for (const gi::Settings* s : {&temporal, &spatial}) {
    const char* name = s == &temporal ? "temporal" : "temporal and spatial";
    const engine::FloatImage mean = directAfter(ctx, picked, *s, 64, true);
    const double relative = meanOf(mean) / meanOf(truth) - 1.0;
    const double worst = worstBlockDifference(mean, truth, kSize);
    const engine::FloatImage frame = directAfter(ctx, picked, *s, 16, false);
    const float peak = *std::max_element(frame.pixels.begin(), frame.pixels.end());
    std::printf("%s: mean %+.2f%%, worst 8x8 block %.2f%%, a frame's brightest pixel %.2f of the exact image's\n", name,
                100.0 * relative, 100.0 * worst, peak / brightest);
    EXPECT_LT(peak, 4.0f * brightest) << name;
    if (s == &temporal) {
      EXPECT_LT(std::abs(relative), 0.01) << name;
      EXPECT_LT(worst, 0.06) << name;
    } else {
      // Spatial reuse keeps the image's mean but moves blocks' (measured: 7% in the worst; its weights
      // leave visibility out): docs/RESULTS.md, and off by default.
      EXPECT_LT(std::abs(relative), 0.02) << name;
    }
  }
  const double treeError = mseOf(directAfter(ctx, picked, base, 16, false), truth);
  const double reservoirError = mseOf(directAfter(ctx, picked, temporal, 16, false), truth);
  std::printf("one frame's MSE: the tree's one pick %.3e, reservoirs with temporal reuse %.3e (%.2fx)\n", treeError,
              reservoirError, reservoirError / treeError);
  EXPECT_LT(reservoirError, treeError / 3.0);
  unload(picked);
  unload(exact);
}

// Model only what a scene requires: with no more point and spot lights than the tree's cut, NEE's sum is
// exact, the reservoirs are not made and their passes do not run, and the image is the one without them
// bit for bit.
TEST_F(ReservoirTest, AScenesExactSumRunsNoReservoirPass) {
  const std::string path = lightField(8, "reservoir_few", true);
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, s, 8));
  ASSERT_FALSE(s.gpu.desc.picksPunctualLights);
  gi::Settings off, on;
  on.reservoirs.enabled = true;
  const engine::FloatImage without = directAfter(ctx, s, off, 2, false);
  const engine::FloatImage with = directAfter(ctx, s, on, 2, false);
  EXPECT_TRUE(sameBits(without, with));
  tools::ModuleSession session;
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, on, session));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  gi::FrameStats stats;
  ASSERT_TRUE(gi::frameStats(session.module, 0, stats));
  for (const gi::PassTiming& pass : stats.passes) EXPECT_EQ(std::string(pass.name).find("reservoir"), std::string::npos);
  for (const std::string& program : gi::programNames(session.module, on)) EXPECT_NE(program, "gi_reservoirs");
  tools::destroyModuleSession(ctx, session);
  unload(s);
}
