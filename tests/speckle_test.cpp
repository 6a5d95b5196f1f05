// What the player sees with the camera still: after 32 frames at 1 spp a
// filtering method's image should have no speckle, no pixel where the
// reference is smooth that lies further from it than 3σ of a 32-sample mean
// (σ: the pixel's one-sample standard deviation, measured from raw frames),
// i.e. noisier or more biased than averaging the 32 frames' samples alone
// would leave it. The reference starts from the same G-buffer (raw's paths,
// 4096 samples), so only the estimator and the filter count. Every bounce
// (B = 31, Russian roulette from the third): nhpsf and anhpsf gather every
// bounce through the map whatever settings.maxBounces says, so a reference of
// fewer bounces would count the missing light as their bias (at B = 1 it
// was 28% of the image's luminance). The hash methods run with hpsf.temporal
// (their direct light reprojected and accumulated; off by default for
// memory, without it their direct light is one frame's samples).
//
// Issue 19 asks this of every method; measured at 64² on the Cornell box
// (counts of 1411 smooth pixels, printed by the test): bilateral 0, atrous 0,
// sspsf 0 (asserted); gif 19 (worst 22σ: the floor in the short box's shadow,
// 3× the reference's light, the guided filter's window reaching the box's
// lit indirect), hpsf 4, nhpsf 2, anhpsf 2, svgf 3 (worst 3.9–4.5σ; svgf's
// are 10–20% too dark). The methods that pass are held to it; the others are
// printed, the open part of the issue.
#include <cmath>

#include "module_test_helpers.h"

class SpeckleTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 64, kFrames = 32;
constexpr uint32_t kBounces = 31;  // every bounce (see above)

double luminance(const engine::FloatImage& img, size_t p) {
  return 0.2126 * img.pixels[3 * p] + 0.7152 * img.pixels[3 * p + 1] + 0.0722 * img.pixels[3 * p + 2];
}

engine::FloatImage lastOfStillFrames(const engine::Context& ctx, const LoadedScene& s, const gi::Settings& settings,
                                     uint32_t frames, std::vector<engine::FloatImage>* each = nullptr) {
  tools::ModuleSession session;
  EXPECT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, settings, session));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  engine::FloatImage last;
  for (uint32_t f = 0; f < frames; ++f) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    if (each || f + 1 == frames) last = tools::readModuleImages(ctx, session).final;
    if (each) each->push_back(last);
  }
  tools::destroyModuleSession(ctx, session);
  return last;
}

}  // namespace

TEST_F(SpeckleTest, NoSpeckleAfter32StillFramesWhereTheReferenceIsSmooth) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  gi::Settings defaults;
  defaults.maxBounces = kBounces;
  // The reference from the same G-buffer: raw's paths accumulated to 4096 samples (another seed).
  gi::Settings converged;
  converged.maxBounces = kBounces;
  converged.seed = 0x5eed;
  converged.raw.samplesPerPixel = 64;
  converged.raw.temporalAccumulation = true;
  engine::ReferenceImages reference;
  reference.final = lastOfStillFrames(ctx, s, converged, 64);
  const size_t pixels = size_t(kSize) * kSize;
  // Each pixel's one-sample σ: raw's frames at 1 spp (independent samples; 64 of them).
  std::vector<engine::FloatImage> raw;
  lastOfStillFrames(ctx, s, defaults, 64, &raw);
  std::vector<double> sigma(pixels);
  for (size_t p = 0; p < pixels; ++p) {
    double sum = 0.0, squares = 0.0;
    for (const engine::FloatImage& f : raw) {
      sum += luminance(f, p);
      squares += luminance(f, p) * luminance(f, p);
    }
    const double mean = sum / double(raw.size());
    sigma[p] = std::sqrt(std::max(0.0, (squares - mean * sum) / double(raw.size() - 1)));
  }
  // Smooth: no edge (every neighbour within 15% of the pixel's luminance) and
  // no kink (their mean within 3% of it: gradients are smooth, shadow
  // boundaries and corners are not).
  std::vector<bool> smooth(pixels, false);
  size_t smoothCount = 0;
  for (uint32_t y = 1; y + 1 < kSize; ++y)
    for (uint32_t x = 1; x + 1 < kSize; ++x) {
      const size_t p = size_t(y) * kSize + x;
      const double l = luminance(reference.final, p);
      bool flat = l > 0.0 && sigma[p] > 0.0;
      double mean = 0.0;
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
          if (i == 0 && j == 0) continue;
          const double n = luminance(reference.final, size_t(int(p) + j * int(kSize) + i));
          flat = flat && std::abs(n - l) <= 0.15 * l;
          mean += n / 8.0;
        }
      smooth[p] = flat && std::abs(mean - l) <= 0.03 * l;
      smoothCount += smooth[p];
    }
  ASSERT_GT(smoothCount, pixels / 8);  // walls and floor away from corners and shadow boundaries
  for (gi::Method method : {gi::Method::Gif, gi::Method::Bilateral, gi::Method::Atrous, gi::Method::Sspsf,
                            gi::Method::Hpsf, gi::Method::Nhpsf, gi::Method::Anhpsf, gi::Method::Svgf}) {
    gi::Settings settings;
    settings.method = method;
    settings.maxBounces = kBounces;
    settings.hpsf.temporalDirect = true;  // the hash methods' direct light accumulated (see above)
    const engine::FloatImage image = lastOfStillFrames(ctx, s, settings, kFrames);
    size_t speckles = 0;
    double worst = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
      if (!smooth[p]) continue;
      const double deviation = std::abs(luminance(image, p) - luminance(reference.final, p)) / (sigma[p] / std::sqrt(double(kFrames)));
      worst = std::max(worst, deviation);
      speckles += deviation > 3.0;
    }
    std::printf("%-10s %zu of %zu smooth pixels beyond 3 sigma (worst %.1f sigma)\n", gi::methodName(method), speckles,
                smoothCount, worst);
    if (method == gi::Method::Bilateral || method == gi::Method::Atrous || method == gi::Method::Sspsf) {
      EXPECT_EQ(speckles, 0u) << gi::methodName(method);
    }
  }
  unload(s);
}
