// gi::Settings::indirectOnly (issue 35 §7): an engine that lights its primary hits itself (shadow maps)
// asks for indirect light alone. The module then traces no shadow ray at the primary hits (fewer rays by
// at least one for every other covered pixel and path), leaves the direct output at 0, composites diffuse albedo × indirect, and
// its indirect light keeps the expectation of the full mode's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gpu_test.h"
#include "module_test_helpers.h"

namespace {

constexpr uint32_t kSize = 32, kFrames = 48;

struct ModeRun {
  engine::ReferenceImages images;
  double raysPerFrame = 0.0;
};

ModeRun runMode(const engine::Context& ctx, const LoadedScene& s, gi::Method method, bool indirectOnly) {
  gi::Settings settings;
  settings.method = method;
  settings.indirectOnly = indirectOnly;
  gi::setTracedSamplesPerPixel(settings, 4);
  settings.raw.temporalAccumulation =
      true;  // raw: the mean of every frame (the still camera), not the last one's noise
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  ScopedSession session(ctx);
  std::string error;
  EXPECT_TRUE(tools::createModuleSession(ctx, s.gpu, {kSize, kSize}, settings, session, error)) << error;
  ModeRun run;
  for (uint32_t f = 0; f < kFrames; ++f) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    run.raysPerFrame += double(gi::stats(session.module).raysTraced) / kFrames;
  }
  run.images = tools::readModuleImages(ctx, session);
  tools::destroyModuleSession(ctx, session);
  return run;
}

}  // namespace

class IndirectOnlyTest : public GpuTest {};

TEST_F(IndirectOnlyTest, NoPrimaryShadowRaysNoDirectLightAndTheSameIndirectLight) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Svgf, gi::Method::Hpsf}) {
    const char* name = gi::methodName(method);
    const ModeRun full = runMode(ctx, s, method, false);
    const ModeRun only = runMode(ctx, s, method, true);
    uint32_t covered = 0;
    double directSum = 0.0, worstComposite = 0.0;
    for (size_t p = 0; p < size_t(kSize) * kSize; ++p) {
      covered += only.images.depth.pixels[p] > 0.0f;
      for (int c = 0; c < 3; ++c) {
        const size_t k = 3 * p + size_t(c);
        directSum += std::fabs(only.images.direct.pixels[k]);
        const double expected = double(only.images.albedo.pixels[k]) * std::max(0.0f, only.images.indirect.pixels[k]);
        worstComposite =
            std::max(worstComposite, std::fabs(only.images.final.pixels[k] - expected) / (expected + 1e-3));
      }
    }
    const double indirectFull = meanOf(full.images.indirect), indirectOnly = meanOf(only.images.indirect);
    std::printf(
        "%s: rays a frame %.0f, indirect-only %.0f (%u covered pixels); mean indirect %.5f and %.5f (%+.2f%%); "
        "composite against albedo x indirect: worst %.2e\n",
        name, full.raysPerFrame, only.raysPerFrame, covered, indirectFull, indirectOnly,
        100.0 * (indirectOnly - indirectFull) / indirectFull, worstComposite);
    EXPECT_EQ(directSum, 0.0) << name;
    EXPECT_LT(worstComposite, 0.01) << name;  // half-float outputs
    // Not every covered pixel traces one (a surface facing away from every light: none), most do.
    EXPECT_LE(only.raysPerFrame, full.raysPerFrame - 0.5 * 4 * covered) << name << ": the primary hits' shadow rays";
    EXPECT_NEAR(indirectOnly, indirectFull, 0.03 * indirectFull) << name;
  }
}
