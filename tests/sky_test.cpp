// The sky (Scene::sky, sky.glsl): the light of rays that leave the scene, for
// the reference and every method; a constant colour and an equirectangular map.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "gi/catalogue.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "procedural_scene.h"

class SkyTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 32;
const glm::vec3 kAlbedo{0.6f, 0.4f, 0.2f};

// An open diffuse plane (y = 0, 200 m wide) seen from 1 m above it; the top
// of the view is sky.
std::string openPlane(const std::string& name) {
  testscene::Description d;
  d.quads.push_back({{{-100, 0, 100}, {100, 0, 100}, {100, 0, -100}, {-100, 0, -100}}, kAlbedo});
  d.eye = {0, 1, 3};
  d.target = {0, 0, 0};
  return testscene::write(d, name);
}

// The same plane with a wall behind it (z = −1, 2 m high): light that
// reaches the plane by a bounce off the wall, and the wall's shadow on it.
std::string planeAndWall(const std::string& name) {
  testscene::Description d;
  d.quads.push_back({{{-100, 0, 100}, {100, 0, 100}, {100, 0, -100}, {-100, 0, -100}}, kAlbedo});
  d.quads.push_back({{{-3, 0, -1}, {3, 0, -1}, {3, 2, -1}, {-3, 2, -1}}, glm::vec3(0.7f)});
  d.eye = {0, 1.5f, 3};
  d.target = {0, 0.5f, -1};
  return testscene::write(d, name);
}

// Every method's final image (frames of a still camera; raw accumulates), or
// with `meanOfFrames` the mean of every frame's final image.
engine::ReferenceImages methodImage(const engine::Context& ctx, LoadedScene& s, gi::Method method, uint32_t frames,
                                    bool meanOfFrames = false) {
  gi::Settings settings;
  settings.method = method;
  settings.maxBounces = 2;
  settings.raw.temporalAccumulation = true;
  ScopedSession session(ctx);
  std::string error;
  EXPECT_TRUE(tools::createModuleSession(ctx, s.gpu, {kSize, kSize}, settings, session, error)) << error;
  if (!session.module) return {};
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  engine::FloatImage sum(kSize, kSize, 3);
  for (uint32_t f = 0; f < frames; ++f) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    if (!meanOfFrames) continue;
    const engine::FloatImage frame = tools::readModuleImages(ctx, session).final;
    for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += frame.pixels[i] / float(frames);
  }
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  if (meanOfFrames) out.final = sum;
  tools::destroyModuleSession(ctx, session);
  return out;
}

// Mean of channel c over the pixels where `depth` says geometry (or, with
// `background`, the pixels where it says none).
double maskedMean(const engine::FloatImage& img, const engine::FloatImage& depth, uint32_t c, bool background = false) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    if ((depth.pixels[p] > 0.0f) != background) {
      sum += img.pixels[p * img.channels + c];
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

}  // namespace

// An open diffuse plane under a constant sky L and nothing else: every plane
// pixel is albedo × L (irradiance π L, times albedo/π), every other pixel L,
// within 1%, for the reference and every method (aaf_ao: no occlusion, AO 1).
TEST_F(SkyTest, OpenPlaneUnderAConstantSkyIsAlbedoTimesSky) {
  engine::Sky sky;
  sky.radiance = {0.8f, 1.0f, 1.2f};
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(openPlane("sky_open_plane"), s, sky));
  ASSERT_TRUE(s.gpu.desc.hasSky);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 16);
  auto check = [&](const engine::ReferenceImages& img, const char* what, bool ambientOcclusion) {
    size_t plane = 0, background = 0, wrong = 0;
    for (size_t p = 0; p < size_t(kSize) * kSize; ++p) {
      const bool covered = img.depth.pixels[p] > 0.0f;
      (covered ? plane : background)++;
      for (uint32_t c = 0; c < 3; ++c) {
        const float expected = ambientOcclusion ? 1.0f : covered ? kAlbedo[c] * sky.radiance[c] : sky.radiance[c];
        wrong += std::fabs(img.final.pixels[3 * p + c] - expected) > 0.01f * expected;
      }
    }
    EXPECT_GT(plane, size_t(kSize * kSize / 4)) << what;
    EXPECT_GT(background, size_t(kSize)) << what;
    EXPECT_EQ(wrong, 0u) << what << ": channels more than 1% from albedo × sky (or the sky)";
  };
  check(ref, "reference", false);
  for (const gi::MethodInfo& info : gi::methodCatalogue())
    check(methodImage(ctx, s, info.method, 2), info.name, info.method == gi::Method::AafAo);
}

// An equirectangular map: a dim upper sky, a bright patch (a "sun") and
// black below the horizon. The plane's radiance is albedo/π × Σ over the
// map's texels of L × ∫cos θ dΩ (texels are read nearest: piecewise
// constant), here computed exactly; the reference (map NEE weighed against
// BSDF sampling), raw (the same, accumulated) and aaf (NEE alone, the mean of
// 32 frames) match it within 1%.
TEST_F(SkyTest, PlaneUnderASkyMapMatchesTheMapsIntegral) {
  engine::Sky sky;
  const uint32_t w = 32, h = 16;
  sky.map = engine::FloatImage(w, h, 3);
  for (uint32_t y = 0; y < h / 2; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      sky.map.at(x, y, 0) = 0.2f + 0.02f * float(x);
      sky.map.at(x, y, 1) = 0.3f;
      sky.map.at(x, y, 2) = 0.5f + 0.05f * float(y);
    }
  for (uint32_t c = 0; c < 3; ++c) sky.map.at(20, 5, c) = 200.0f;  // the sun, 33°–45° above the horizon
  sky.radiance = glm::vec3(1.5f);
  sky.mapPath = "procedural";
  glm::dvec3 expected(0.0);
  for (uint32_t y = 0; y < h / 2; ++y) {
    const double s0 = std::sin(std::numbers::pi * y / h), s1 = std::sin(std::numbers::pi * (y + 1) / h);
    const double cosineSolidAngle =
        (2.0 * std::numbers::pi / w) * (s1 * s1 - s0 * s0) / 2.0;  // ∫ cos θ dΩ over one texel
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t c = 0; c < 3; ++c) expected[c] += sky.map.at(x, y, c) * sky.radiance[c] * cosineSolidAngle;
  }
  for (uint32_t c = 0; c < 3; ++c) expected[c] *= kAlbedo[c] / std::numbers::pi;

  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(openPlane("sky_map_plane"), s, sky));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 1, 256);
  struct Run {
    const char* what;
    engine::ReferenceImages images;
  };
  const Run runs[] = {{"reference", ref},
                      {"raw", methodImage(ctx, s, gi::Method::Raw, 64)},
                      {"aaf", methodImage(ctx, s, gi::Method::Aaf, 32, true)}};
  for (const Run& r : runs)
    for (uint32_t c = 0; c < 3; ++c) {
      const double mean = maskedMean(r.images.final, r.images.depth, c);
      std::printf("%-9s channel %u: %.5f, expected %.5f\n", r.what, c, mean, expected[c]);
      EXPECT_NEAR(mean, expected[c], 0.01 * expected[c]) << r.what << " channel " << c;
    }
}

// Light from the sky through a bounce: a wall behind the plane shades it and
// reflects sky light onto it. Every method's mean over the image is the
// reference's within 5% (one frame's noise and each filter's bias; the
// extremes tests allow 10%).
TEST_F(SkyTest, EveryMethodMatchesTheReferenceWithABounce) {
  engine::Sky sky;
  sky.radiance = {0.8f, 1.0f, 1.2f};
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(planeAndWall("sky_plane_wall"), s, sky));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 512);
  const double refMean = meanOf(ref.final);
  for (const gi::MethodInfo& info : gi::methodCatalogue()) {
    const gi::Method m = info.method;
    if (m == gi::Method::AafAo) continue;
    engine::ReferenceImages img = methodImage(ctx, s, m, 8);
    const double mean = meanOf(img.final);
    std::printf("%-9s mean %.5f, reference %.5f (%+.2f%%)\n", gi::methodName(m), mean, refMean,
                100.0 * (mean / refMean - 1.0));
    EXPECT_NEAR(mean, refMean, 0.05 * refMean) << gi::methodName(m);
  }
}
