// The guided filter on the GPU against a double-precision CPU implementation,
// and its behaviour at the edges of its parameters.
#include <cstring>
#include <random>

#include "screen_filter_fixture.h"

namespace {

constexpr uint32_t W = 40, H = 32;
using Rgba = std::vector<float>;  // W×H×4

// The CPU reference: He et al.'s guided filter with clipped windows, the same
// guidance masking and ridge terms as the GPU, all in double precision.
// Background pixels (covered[p] = 0) enter no window: window means are over
// covered pixels, each window's coefficients count by its covered fraction,
// and a background pixel keeps its input.
std::vector<double> guidedFilterCpu(const Rgba& guidance, const Rgba& input, int r, uint32_t dims, double epsN,
                                    double epsD, const std::vector<float>& covered = {}) {
  auto cover = [&](int x, int y) { return covered.empty() ? 1.0 : double(covered[size_t(y) * W + x]); };
  auto guide = [&](int x, int y, int i) {
    const float* g = &guidance[(size_t(y) * W + x) * 4];
    if (dims == 1) return i == 0 ? (double(g[0]) + g[1] + g[2]) / 3.0 : 0.0;
    if (dims == 3) return i < 3 ? double(g[i]) : 0.0;
    return double(g[i]);
  };
  auto in = [&](int x, int y, int c) { return double(input[(size_t(y) * W + x) * 4 + c]); };
  std::vector<double> a(size_t(W) * H * 12), b(size_t(W) * H * 3), weight(size_t(W) * H);
  for (int y = 0; y < int(H); ++y)
    for (int x = 0; x < int(W); ++x) {
      double n = 0, total = 0, mI[4] = {}, mII[4][4] = {}, mP[3] = {}, mIP[4][3] = {};
      for (int yy = std::max(0, y - r); yy <= std::min(int(H) - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(int(W) - 1, x + r); ++xx) {
          ++total;
          double w = cover(xx, yy);
          if (w == 0.0) continue;
          ++n;
          for (int i = 0; i < 4; ++i) {
            mI[i] += guide(xx, yy, i);
            for (int j = 0; j < 4; ++j) mII[i][j] += guide(xx, yy, i) * guide(xx, yy, j);
            for (int c = 0; c < 3; ++c) mIP[i][c] += guide(xx, yy, i) * in(xx, yy, c);
          }
          for (int c = 0; c < 3; ++c) mP[c] += in(xx, yy, c);
        }
      weight[size_t(y) * W + x] = n / total;
      if (n == 0) continue;  // no covered pixel: the window counts for nothing
      double S[4][4];
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) S[i][j] = mII[i][j] / n - (mI[i] / n) * (mI[j] / n);
      for (int i = 0; i < 4; ++i) S[i][i] += std::max(i < 3 ? epsN : epsD, 1e-7);
      for (int c = 0; c < 3; ++c) {
        // Gaussian elimination on [S | cov].
        double M[4][5];
        for (int i = 0; i < 4; ++i) {
          for (int j = 0; j < 4; ++j) M[i][j] = S[i][j];
          M[i][4] = mIP[i][c] / n - (mI[i] / n) * (mP[c] / n);
        }
        for (int k = 0; k < 4; ++k)
          for (int i = k + 1; i < 4; ++i) {
            double f = M[i][k] / M[k][k];
            for (int j = k; j < 5; ++j) M[i][j] -= f * M[k][j];
          }
        double sol[4];
        for (int i = 3; i >= 0; --i) {
          double s = M[i][4];
          for (int j = i + 1; j < 4; ++j) s -= M[i][j] * sol[j];
          sol[i] = s / M[i][i];
        }
        double bb = mP[c] / n;
        for (int i = 0; i < 4; ++i) {
          a[(size_t(y) * W + x) * 12 + 3 * i + c] = sol[i];
          bb -= sol[i] * mI[i] / n;
        }
        b[(size_t(y) * W + x) * 3 + c] = bb;
      }
    }
  std::vector<double> q(size_t(W) * H * 3);
  for (int y = 0; y < int(H); ++y)
    for (int x = 0; x < int(W); ++x) {
      double n = 0, ma[12] = {}, mb[3] = {};
      for (int yy = std::max(0, y - r); yy <= std::min(int(H) - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(int(W) - 1, x + r); ++xx) {
          double w = weight[size_t(yy) * W + xx];
          n += w;
          for (int k = 0; k < 12; ++k) ma[k] += w * a[(size_t(yy) * W + xx) * 12 + k];
          for (int c = 0; c < 3; ++c) mb[c] += w * b[(size_t(yy) * W + xx) * 3 + c];
        }
      for (int c = 0; c < 3; ++c) {
        double v = in(x, y, c);
        if (cover(x, y) != 0.0 && n > 0.0) {
          v = mb[c] / n;
          for (int i = 0; i < 4; ++i) v += ma[3 * i + c] / n * guide(x, y, i);
        }
        q[(size_t(y) * W + x) * 3 + c] = v;
      }
    }
  return q;
}

}  // namespace

class GuidedFilterTest : public ScreenFilterTest<W, H> {
 protected:
  // gif.subsample the statistics images are made for (the filter runs at their resolution).
  virtual uint32_t subsample() const { return 1; }
  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(ScreenFilterTest::SetUp());
    ASSERT_FALSE(gi::ensureGuidedStack(dev, filters, subsample()));
  }
  // `covered`: 1 per covered pixel, 0 for background, whose guidance depth (w) is then 0, as the module's
  // guidance pass writes it (the filter's coverage); empty = every pixel covered (`guidance` has no depth 0).
  std::vector<float> run(const Rgba& guidance, const Rgba& input, const gi::GuidedFilterParams& params,
                         const std::vector<float>& covered = {}) {
    Rgba guide = guidance;
    for (size_t p = 0; p < size_t(W) * H; ++p) {
      if (!covered.empty() && covered[p] == 0.0f) guide[4 * p + 3] = 0.0f;
      EXPECT_TRUE(!covered.empty() || guide[4 * p + 3] > 0.0f) << "pixel " << p << " would be background";
    }
    upload(kGuidance, guide);
    upload(kInput, input);
    return filterOutput([&](VkCommandBuffer cmd) { gi::recordGuidedFilter(dev, cmd, filters, params, {}); }, 3);
  }

  // Left half faces +z at depth 0.3, right half faces +x at depth 0.6; the input is 0.2 / 0.8 plus
  // uniform noise of ±0.15. Each side's mean is kept within 0.02 and its noise falls below 0.35 of
  // the input's; the columns either side of the step stay more than 0.5 apart.
  void expectStepKeptAndSidesSmoothed(const gi::GuidedFilterParams& params, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-0.15f, 0.15f);
    Rgba guidance(size_t(W) * H * 4), input(size_t(W) * H * 4);
    for (uint32_t y = 0; y < H; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        const bool left = x < W / 2;
        const float g[4] = {left ? 0.5f : 1.0f, 0.5f, left ? 1.0f : 0.5f, left ? 0.3f : 0.6f};
        std::memcpy(&guidance[(size_t(y) * W + x) * 4], g, sizeof(g));
        const float v = (left ? 0.2f : 0.8f) + noise(rng);
        for (int c = 0; c < 4; ++c) input[(size_t(y) * W + x) * 4 + c] = v;
      }
    const std::vector<float> out = run(guidance, input, params);
    auto stats = [&](const auto& img, size_t stride, uint32_t x0, uint32_t x1, double& mean, double& sd) {
      double s = 0, s2 = 0, n = 0;
      for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
          const double v = img[(size_t(y) * W + x) * stride];
          s += v;
          s2 += v * v;
          ++n;
        }
      mean = s / n;
      sd = std::sqrt(std::max(0.0, s2 / n - mean * mean));
    };
    double inMean, inSd, outMean, outSd;
    for (auto [x0, x1, expected] : {std::tuple{0u, W / 2, 0.2}, std::tuple{W / 2, W, 0.8}}) {
      stats(input, 4, x0, x1, inMean, inSd);
      stats(out, 3, x0, x1, outMean, outSd);
      EXPECT_NEAR(outMean, expected, 0.02);
      EXPECT_LT(outSd, 0.35 * inSd) << "noise on side [" << x0 << ", " << x1 << ")";
    }
    double l, r, sd;
    stats(out, 3, W / 2 - 1, W / 2, l, sd);
    stats(out, 3, W / 2, W / 2 + 1, r, sd);
    EXPECT_GT(r - l, 0.5);
  }

  static Rgba random(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Rgba v(size_t(W) * H * 4);
    for (float& x : v) x = u(rng);
    return v;
  }
};

TEST_F(GuidedFilterTest, MatchesDoublePrecisionCpuReference) {
  Rgba guidance = random(1), input = random(2);
  for (uint32_t dims : {1u, 3u, 4u})
    for (int radius : {1, 4, 24}) {
      gi::GuidedFilterParams params{uint32_t(radius), 0.01f, 0.02f, dims, false};
      std::vector<float> gpu = run(guidance, input, params);
      std::vector<double> cpu = guidedFilterCpu(guidance, input, radius, dims, 0.01, 0.02);
      double worst = 0.0;
      for (size_t i = 0; i < cpu.size(); ++i) worst = std::max(worst, std::abs(double(gpu[i]) - cpu[i]));
      EXPECT_LT(worst, 1e-4) << "dims " << dims << ", radius " << radius;
    }
}

TEST_F(GuidedFilterTest, ConstantInputStaysConstant) {
  Rgba input(size_t(W) * H * 4, 0.7f);
  std::vector<float> out = run(random(3), input, {8, 0.01f, 0.02f, 4, false});
  for (float v : out) ASSERT_NEAR(v, 0.7f, 1e-5f);
}

TEST_F(GuidedFilterTest, SmoothsEachSideOfAGuidanceStepAndKeepsTheStep) {
  expectStepKeptAndSidesSmoothed({6, 0.01f, 0.02f, 4, false}, 4);
}

TEST_F(GuidedFilterTest, EpsilonExtremesStayFiniteAndReachTheirLimits) {
  Rgba guidance = random(5), input(size_t(W) * H * 4);
  // Input exactly linear in the guidance: a tiny ε recovers it (best linear fit).
  for (size_t p = 0; p < size_t(W) * H; ++p)
    for (int c = 0; c < 4; ++c) input[4 * p + c] = 2.0f * guidance[4 * p] - 0.5f * guidance[4 * p + 3] + 0.25f;
  std::vector<float> tiny = run(guidance, input, {4, 0.0f, 0.0f, 4, false});
  for (size_t p = 0; p < size_t(W) * H; ++p)
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(tiny[3 * p + c]));
      ASSERT_NEAR(tiny[3 * p + c], input[4 * p + c], 2e-3f);
    }
  // A huge ε flattens a to 0: the output is the box mean of the box mean of the input.
  Rgba noisy = random(6);
  std::vector<float> huge = run(guidance, noisy, {4, 1e6f, 1e6f, 4, false});
  std::vector<double> expected = guidedFilterCpu(guidance, noisy, 4, 4, 1e6, 1e6);
  for (size_t i = 0; i < expected.size(); ++i) {
    ASSERT_TRUE(std::isfinite(huge[i]));
    ASSERT_NEAR(huge[i], expected[i], 1e-4);
  }
  // Flat guidance (zero variance everywhere) with ε = 0 relies on the floor: still finite.
  Rgba flat(size_t(W) * H * 4, 0.5f);
  for (float v : run(flat, noisy, {4, 0.0f, 0.0f, 4, false})) ASSERT_TRUE(std::isfinite(v));
}

// Background enters no window. The G-buffer gives background a made-up grey
// guidance (normal 0.5, depth 0); with 1-D guidance a grey normal cannot be
// told from real geometry, so the background's black used to bleed into the
// silhouette. Here an object lit evenly (input 1) whose grey guidance is also
// 0.5 sits on background (input 0): every covered pixel must stay 1, and a
// random coverage mask matches the CPU reference.
TEST_F(GuidedFilterTest, BackgroundEntersNoWindow) {
  Rgba guidance(size_t(W) * H * 4), input(size_t(W) * H * 4, 0.0f);
  std::vector<float> covered(size_t(W) * H, 0.0f);
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      size_t p = size_t(y) * W + x;
      bool object = (x - W / 2.0f) * (x - W / 2.0f) + (y - H / 2.0f) * (y - H / 2.0f) < 100.0f;
      covered[p] = object ? 1.0f : 0.0f;
      // The object's normal (1, −1, 0)/√2 maps to (0.854, 0.146, 0.5): grey 0.5, like the background's.
      float g[4] = {object ? 0.8535534f : 0.5f, object ? 0.1464466f : 0.5f, 0.5f, object ? 0.4f : 0.0f};
      std::memcpy(&guidance[4 * p], g, sizeof(g));
      for (int c = 0; c < 3; ++c) input[4 * p + c] = object ? 1.0f : 0.0f;
    }
  for (uint32_t dims : {1u, 4u}) {
    std::vector<float> out = run(guidance, input, {8, 0.01f, 0.02f, dims, false}, covered);
    for (size_t p = 0; p < size_t(W) * H; ++p)
      if (covered[p] > 0.0f) {
        ASSERT_NEAR(out[3 * p], 1.0f, 1e-4f) << "dims " << dims << ", pixel " << p;
      }
  }
  std::mt19937 rng(7);
  std::bernoulli_distribution keep(0.7);
  for (float& c : covered) c = keep(rng) ? 1.0f : 0.0f;
  Rgba g = random(8), noisy = random(9);
  for (uint32_t dims : {1u, 4u}) {
    std::vector<float> gpu = run(g, noisy, {4, 0.01f, 0.02f, dims, false}, covered);
    std::vector<double> cpu = guidedFilterCpu(g, noisy, 4, dims, 0.01, 0.02, covered);
    double worst = 0.0;
    for (size_t i = 0; i < cpu.size(); ++i) worst = std::max(worst, std::abs(double(gpu[i]) - cpu[i]));
    EXPECT_LT(worst, 1e-4) << "dims " << dims;
  }
}

// The fast guided filter (gif.subsample = s): window statistics of s×s blocks, coefficients bilinear
// between them. With s = 3 on a 40×32 image the last blocks are partial. What the filter must keep
// whatever its resolution: a constant stays, an input linear in the guidance is recovered (every window
// fits the same a and b, so their interpolation is exact), an evenly lit object keeps its light beside
// background, and a guidance step keeps its step while each side is smoothed.
class GuidedFilterSubsampledTest : public GuidedFilterTest {
 protected:
  uint32_t subsample() const override { return 3; }
  static gi::GuidedFilterParams params(uint32_t radius, float epsilon, uint32_t dims) {
    return {.radius = radius, .epsilonNormal = epsilon, .epsilonDepth = epsilon, .guidanceDimensions = dims};
  }
};

TEST_F(GuidedFilterSubsampledTest, KeepsConstantsLinearFitsAndLitObjects) {
  const Rgba guidance = random(11);
  const Rgba constant(size_t(W) * H * 4, 0.7f);
  for (float v : run(guidance, constant, params(8, 0.01f, 4))) ASSERT_NEAR(v, 0.7f, 1e-5f);
  Rgba linear(size_t(W) * H * 4);
  for (size_t p = 0; p < size_t(W) * H; ++p)
    for (int c = 0; c < 4; ++c) linear[4 * p + c] = 2.0f * guidance[4 * p] - 0.5f * guidance[4 * p + 3] + 0.25f;
  const std::vector<float> fit = run(guidance, linear, params(4, 0.0f, 4));
  for (size_t p = 0; p < size_t(W) * H; ++p)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(fit[3 * p + c], linear[4 * p + c], 2e-3f) << "pixel " << p;
  // A disc lit 1 with grey guidance, as the background's, on background lit 0.
  Rgba grey(size_t(W) * H * 4), disc(size_t(W) * H * 4, 0.0f);
  std::vector<float> covered(size_t(W) * H, 0.0f);
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const size_t p = size_t(y) * W + x;
      const bool object = (x - W / 2.0f) * (x - W / 2.0f) + (y - H / 2.0f) * (y - H / 2.0f) < 100.0f;
      covered[p] = object ? 1.0f : 0.0f;
      const float g[4] = {object ? 0.8535534f : 0.5f, object ? 0.1464466f : 0.5f, 0.5f, object ? 0.4f : 0.0f};
      std::memcpy(&grey[4 * p], g, sizeof(g));
      for (int c = 0; c < 3; ++c) disc[4 * p + c] = object ? 1.0f : 0.0f;
    }
  for (uint32_t dims : {1u, 4u}) {
    const std::vector<float> out = run(grey, disc, params(8, 0.01f, dims), covered);
    for (size_t p = 0; p < size_t(W) * H; ++p)
      if (covered[p] > 0.0f) {
        ASSERT_NEAR(out[3 * p], 1.0f, 1e-4f) << "dims " << dims << ", pixel " << p;
      }
  }
}

TEST_F(GuidedFilterSubsampledTest, SmoothsEachSideOfAGuidanceStepAndKeepsTheStep) {
  expectStepKeptAndSidesSmoothed(params(6, 0.01f, 4), 12);
}
