// Path space filtering as Meijer's thesis describes it, through the module:
// the filter vertex (the first vertex with a diffuse lobe) for hpsf and sspsf
// alike, anhpsf's continuation depth counted in segments, and nhpsf/anhpsf's
// direct light averaged over every sample.
#include <algorithm>
#include <cmath>

#include "gpu_test.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "procedural_scene.h"

class PathFilteringFidelityTest : public GpuTest {
 protected:
  // A floor whose left half is glossy plastic (a GGX lobe over a diffuse
  // one) and right half polished metal (no diffuse lobe), a grey back wall,
  // a point light.
  static void plasticAndMetal(LoadedScene& s) {
    testscene::Description d;
    testscene::Quad plastic{{{-1, 0, 1}, {0, 0, 1}, {0, 0, -1}, {-1, 0, -1}}, glm::vec3(0.7f, 0.6f, 0.5f)};
    plastic.roughness = 0.3f;
    testscene::Quad metal{{{0, 0, 1}, {1, 0, 1}, {1, 0, -1}, {0, 0, -1}}, glm::vec3(0.9f)};
    metal.roughness = 0.3f;
    metal.metallic = 1.0f;
    d.quads = {plastic, metal, {{{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, glm::vec3(0.8f)}};
    d.lights.push_back({{0, 1.2f, 0.3f}, glm::vec3(3.0f)});
    d.eye = {0, 1.0f, 2.0f};
    d.target = {0, 0.1f, -0.3f};
    load(testscene::write(d, "fidelity_plastic_metal"), s);
  }
  static bool isPlastic(const engine::ReferenceImages& m, uint32_t x, uint32_t y) {
    return std::abs(m.albedo.at(x, y, 0) - 0.7f) < 0.02f && std::abs(m.albedo.at(x, y, 2) - 0.5f) < 0.02f;
  }
  static bool isMetal(const engine::ReferenceImages& m, uint32_t x, uint32_t y) {
    return std::abs(m.albedo.at(x, y, 0) - 0.9f) < 0.02f && std::abs(m.albedo.at(x, y, 2) - 0.9f) < 0.02f;
  }
};

// Meijer's filter criterion is the first vertex with a diffuse lobe: glossy
// plastic has one and is filtered (its cell is found), a pure metal has none
// and keeps its own sample (no cell). The hash map's "found" view: green =
// cell used, red = no cell.
TEST_F(PathFilteringFidelityTest, HpsfFiltersAtTheFirstVertexWithADiffuseLobe) {
  LoadedScene s;
  plasticAndMetal(s);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  settings.debugView = gi::DebugView::HashFound;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  for (uint32_t f = 0; f < 2; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  size_t plastic = 0, plasticFound = 0, metal = 0, metalFound = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      bool found = out.final.at(x, y, 1) == 1.0f && out.final.at(x, y, 0) == 0.0f;
      if (isPlastic(out, x, y)) plastic++, plasticFound += found;
      if (isMetal(out, x, y)) metal++, metalFound += found;
    }
  ASSERT_GT(plastic, 50u);
  ASSERT_GT(metal, 50u);
  EXPECT_EQ(plasticFound, plastic) << "glossy plastic has a diffuse lobe: it is a filter vertex";
  EXPECT_EQ(metalFound, 0u) << "a pure metal has no diffuse lobe";
}

// sspsf follows the same rule: metal pixels keep their own sample (the same
// paths raw traces, within the half floats' rounding), plastic pixels are filtered.
TEST_F(PathFilteringFidelityTest, SspsfFollowsTheSameFilterVertexRule) {
  LoadedScene s;
  plasticAndMetal(s);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::ReferenceImages images[2];
  for (gi::Method method : {gi::Method::Raw, gi::Method::Sspsf}) {
    gi::Settings settings;
    settings.method = method;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    images[method == gi::Method::Sspsf] = tools::readModuleImages(ctx, session);
  }
  size_t metal = 0, metalKept = 0, plastic = 0, plasticChanged = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      // Raw's sample reaches sspsf's output through the indirect history it filters, rounded to half floats
      // at the history's scale there and back (at most 2 steps of 2^-11 of the value); a filtered pixel
      // moves by its noise.
      bool same = true;
      for (int c = 0; c < 3; ++c) {
        const float a = images[0].indirect.at(x, y, c), b = images[1].indirect.at(x, y, c);
        same &= std::abs(a - b) <= std::max(std::abs(a), std::abs(b)) / 512.0f;
      }
      if (isMetal(images[1], x, y)) metal++, metalKept += same;
      if (isPlastic(images[1], x, y)) plastic++, plasticChanged += !same;
    }
  ASSERT_GT(metal, 50u);
  EXPECT_EQ(metalKept, metal) << "sspsf filtered a pixel without a diffuse lobe";
  EXPECT_GT(plasticChanged, plastic * 9 / 10) << "sspsf left glossy plastic unfiltered";
}

// continuationDepth counts segments, as pathDepth does: N = 2 continues each
// walk by a second segment (which transports light), and no walk goes past N.
TEST_F(PathFilteringFidelityTest, AnhpsfContinuationDepthCountsSegments) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 24, 24, nullptr);
  for (uint32_t depth : {2u, 4u}) {
    gi::Settings settings;
    settings.method = gi::Method::Anhpsf;
    settings.hpsf.continuationDepth = depth;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {24, 24}, settings, session));
    double transported = 0.0;
    float deepest = 0.0f;
    for (uint32_t f = 0; f < 6; ++f) {
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
      gi::FrameStats st = gi::stats(session.module);
      transported += st.hash.transported;
      deepest = std::max(deepest, st.hash.meanContinuationDepth);
      EXPECT_LE(st.hash.meanContinuationDepth, float(depth)) << "depth " << depth;
    }
    EXPECT_GT(transported, 0.0) << "continuationDepth = " << depth << " never continued a walk";
    EXPECT_GT(deepest, float(depth) - 1.0f) << "walks reach " << depth << " segments";
  }
}

// nhpsf and anhpsf take one next-event sample per path, like hpsf and raw:
// 8 paths per pixel cut the direct light's error against the reference by
// about 8× (it is one frame, nothing else averages it).
TEST_F(PathFilteringFidelityTest, NhpsfDirectLightAveragesEverySample) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::FloatImage reference = pixelCentreReference(ctx, s, cam, 1, 2048).direct;
  for (gi::Method method : {gi::Method::Nhpsf, gi::Method::Anhpsf}) {
    double error[2];
    for (uint32_t spp : {1u, 8u}) {
      gi::Settings settings;
      settings.method = method;
      settings.hpsf.samplesPerPixel = spp;
      ScopedSession session(ctx);
      ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
      error[spp == 8] = metrics::mse(tools::readModuleImages(ctx, session).direct, reference);
    }
    std::printf("%s direct MSE at 1 / 8 spp: %.3g / %.3g\n", gi::methodName(method), error[0], error[1]);
    EXPECT_LT(error[1], error[0] / 4.0) << gi::methodName(method) << ": direct light ignores the extra samples";
  }
}
