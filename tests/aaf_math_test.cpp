// Axis-aligned filtering's formulas (shared/aaf.h, the same code the shaders
// run) against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include <cmath>
#include <set>

#include <cmath>

#include "shared/aaf.h"

TEST(AafMath, FilterWidthTakesTheSmallerBandLimit) {
  // μ = 0.9, Ω = 2.8, z_min = 0.5 m, α = 0.3, d = 0.01 m:
  // Ω/z_min = 5.6 < α/d = 30, so Ω_x = 0.9·5.6 = 5.04 and β = 2/5.04.
  EXPECT_NEAR(gpu::aafBandwidth(0.9f, 2.8f, 0.5f, 0.3f, 0.01f), 5.04f, 1e-5f);
  EXPECT_NEAR(gpu::aafBeta(0.9f, 2.8f, 0.5f, 0.3f, 0.01f), 2.0f / 5.04f, 1e-6f);
  // A near reflector (z_min = 0.05 m) and a large pixel (d = 0.1 m): α/d = 3 < Ω/z_min = 56.
  EXPECT_NEAR(gpu::aafBandwidth(0.9f, 2.8f, 0.05f, 0.3f, 0.1f), 0.9f * 3.0f, 1e-5f);
  EXPECT_NEAR(gpu::aafBeta(0.9f, 2.8f, 0.05f, 0.3f, 0.1f), 2.0f / 2.7f, 1e-6f);
}

namespace {
// Mehta et al. eq. 21 as the paper writes it, in double precision, unclamped:
// γ(μΩ√A_p/z_min + α)²·Ω²·(1 + μ z_max/z_min)², with √A_p = d the pixel's footprint.
double paperSamples(double mu, double omega, double gamma, double zMin, double zMax, double alpha, double d) {
  return gamma * std::pow(mu * omega * d / zMin + alpha, 2) * omega * omega * std::pow(1.0 + mu * zMax / zMin, 2);
}
}  // namespace

TEST(AafMath, SampleCountAndBothClamps) {
  // Between the clamps the formula shows through, for several surroundings.
  for (auto [mu, zMin, zMax] : {std::tuple{1.0f, 0.2f, 1.0f}, std::tuple{1.0f, 0.25f, 2.0f},
                                std::tuple{2.0f, 0.4f, 1.0f}, std::tuple{1.0f, 0.3f, 1.5f}}) {
    const double expected = paperSamples(mu, 2.8, 0.4, zMin, zMax, 0.3, 0.01);
    ASSERT_GT(expected, 16.0);
    ASSERT_LT(expected, 100.0 * mu);
    EXPECT_NEAR(gpu::aafSamples(mu, 2.8f, 0.4f, zMin, zMax, 0.3f, 0.01f), expected, 1e-4 * expected)
        << mu << zMin << zMax;
  }
  // Near reflectors ask for more than 100·μ (the formula gives 127.65 here): the upper clamp.
  ASSERT_GT(paperSamples(1.0, 2.8, 0.4, 0.1, 1.0, 0.3, 0.01), 100.0);
  EXPECT_FLOAT_EQ(gpu::aafSamples(1.0f, 2.8f, 0.4f, 0.1f, 1.0f, 0.3f, 0.01f), 100.0f);
  // Far, flat surroundings ask for fewer than 16: the lower clamp.
  ASSERT_LT(paperSamples(0.9, 2.8, 0.4, 5.0, 5.0, 0.3, 0.01), 16.0);
  EXPECT_FLOAT_EQ(gpu::aafSamples(0.9f, 2.8f, 0.4f, 5.0f, 5.0f, 0.3f, 0.01f), 16.0f);
  // μ small enough that 100·μ < 16 still allows the 16 initial samples.
  EXPECT_FLOAT_EQ(gpu::aafSamples(0.1f, 2.8f, 0.4f, 0.1f, 1.0f, 0.3f, 0.01f), 16.0f);
}

TEST(AafMath, ZMinClampAndGlossyBandLimit) {
  EXPECT_FLOAT_EQ(gpu::aafClampZMin(0.0f, 10.0f), 0.2f);  // 2% of a 10 m scene
  EXPECT_FLOAT_EQ(gpu::aafClampZMin(0.5f, 10.0f), 0.5f);
  // Eq. 18: Ω_h,s = 3.6 + 0.084 m; the paper's m = 20 gives γ = 0.11.
  EXPECT_NEAR(gpu::aafOmegaGlossy(20.0f), 3.6f + 1.68f, 1e-5f);
  EXPECT_NEAR(gpu::aafGammaGlossy(20.0f), 0.118f, 0.001f);  // the paper rounds it to 0.11
  EXPECT_GT(gpu::aafOmegaGlossy(100.0f), gpu::aafOmegaGlossy(20.0f));
  // GGX α → Blinn-Phong m = 2/α² − 2 (Walter et al. 2007): α = 0.5 gives m = 6; α = 1 would give 0, clamped to 1.
  EXPECT_FLOAT_EQ(gpu::aafPhongExponent(0.5f), 6.0f);
  EXPECT_FLOAT_EQ(gpu::aafPhongExponent(1.0f), 1.0f);
  // A glossy receiver's band limit is wider than a diffuse one's, so its β is narrower
  // (roughness 0.5 → α = 0.25 → m = 30 → Ω = 6.12, β = 2·z_min/(μ·Ω) where z_min limits).
  float m = gpu::aafPhongExponent(0.25f);
  EXPECT_FLOAT_EQ(m, 30.0f);
  EXPECT_NEAR(gpu::aafBeta(1.0f, gpu::aafOmegaGlossy(m), 0.5f, 0.3f, 0.001f), 2.0f * 0.5f / 6.12f, 1e-5f);
  EXPECT_LT(gpu::aafBeta(1.0f, gpu::aafOmegaGlossy(m), 0.5f, 0.3f, 0.001f),
            gpu::aafBeta(1.0f, AAF_OMEGA_DIFFUSE, 0.5f, 0.3f, 0.001f));
}

// Footnote 7: d, a pixel's world size on the receiver, includes foreshortening
// (capped at AAF_MIN_COS_VIEW).
TEST(AafMath, PixelFootprintIncludesForeshortening) {
  EXPECT_FLOAT_EQ(gpu::aafPixelFootprint(2.0f, 0.01f, 1.0f), 0.02f);
  EXPECT_FLOAT_EQ(gpu::aafPixelFootprint(2.0f, 0.01f, 0.5f), 0.04f);
  EXPECT_FLOAT_EQ(gpu::aafPixelFootprint(2.0f, 0.01f, -0.5f), 0.04f);
  EXPECT_FLOAT_EQ(gpu::aafPixelFootprint(2.0f, 0.01f, 0.0f), 0.02f / float(AAF_MIN_COS_VIEW));
}

// Pass 2's samples are stratified: n samples take n different cells of a
// ⌈√n⌉² grid, for any n and any offset.
TEST(AafMath, SecondPassSamplesAreStratified) {
  for (uint32_t n : {1u, 2u, 5u, 16u, 17u, 48u, 84u, 100u, 900u})
    for (uint32_t offset : {0u, 7u, 123456u}) {
      std::set<std::pair<int, int>> cells;
      float size = 0.0f;
      for (uint32_t i = 0; i < n; ++i) {
        glm::vec2 corner = gpu::aafStratum(i, n, offset, size);
        ASSERT_GE(corner.x, 0.0f);
        ASSERT_LT(corner.x + size, 1.0f + 1e-6f);
        ASSERT_LT(corner.y + size, 1.0f + 1e-6f);
        cells.insert({int(std::lround(corner.x / size)), int(std::lround(corner.y / size))});
      }
      uint32_t side = uint32_t(std::ceil(std::sqrt(double(n))));
      EXPECT_FLOAT_EQ(size, 1.0f / float(side)) << n;
      EXPECT_EQ(cells.size(), n) << n << " samples, offset " << offset << ": two in one cell";
    }
}
