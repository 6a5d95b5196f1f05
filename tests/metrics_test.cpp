// Metrics against values worked out by hand on tiny images, and the
// equal-error fit on synthetic 1/spp data.
#include <gtest/gtest.h>

#include <cmath>

#include "metrics.h"

namespace {
engine::FloatImage constant(uint32_t w, uint32_t h, float v) {
  engine::FloatImage img(w, h, 3);
  for (float& p : img.pixels) p = v;
  return img;
}
}  // namespace

TEST(Metrics, MseRelMseAndPsnrByHand) {
  engine::FloatImage ref = constant(2, 1, 0.5f), img = constant(2, 1, 0.5f);
  img.at(0, 0, 0) = 0.7f;  // one channel of one pixel off by 0.2 → 0.04 over 6 values
  EXPECT_NEAR(metrics::mse(img, ref), 0.04 / 6.0, 1e-8);
  EXPECT_NEAR(metrics::relMse(img, ref), 0.04 / (0.25 + 0.01) / 6.0, 1e-7);  // 0.7f − 0.5f is not 0.2 exactly
  EXPECT_NEAR(metrics::psnrFromMse(0.01), 20.0, 1e-9);
  EXPECT_NEAR(metrics::psnrFromMse(metrics::mse(img, ref)), 10.0 * std::log10(6.0 / 0.04), 1e-6);
  EXPECT_TRUE(std::isinf(metrics::psnrFromMse(0.0)));
}

TEST(Metrics, SsimByHand) {
  // Identical images: 1. Two constant images: no variance, so SSIM is the
  // luminance term (2·μx·μy + C1) / (μx² + μy² + C1) everywhere.
  engine::FloatImage a = constant(16, 16, 0.25f), b = constant(16, 16, 0.75f);
  EXPECT_NEAR(metrics::ssim(a, a), 1.0, 1e-12);
  const double c1 = 1e-4, expected = (2 * 0.25 * 0.75 + c1) / (0.25 * 0.25 + 0.75 * 0.75 + c1);
  EXPECT_NEAR(metrics::ssim(a, b), expected, 1e-9);
  // Noise lowers it; values above 1 clamp (HDR pixels count as white).
  engine::FloatImage noisy = a;
  for (size_t i = 0; i < noisy.pixels.size(); i += 3)
    noisy.pixels[i] = noisy.pixels[i + 1] = noisy.pixels[i + 2] = (i / 3) % 2 ? 0.0f : 0.5f;
  EXPECT_LT(metrics::ssim(noisy, a), 0.5);
  EXPECT_NEAR(metrics::ssim(constant(8, 8, 5.0f), constant(8, 8, 1.0f)), 1.0, 1e-12);
}

TEST(Metrics, EqualErrorFitRecoversTheInverseLaw) {
  // Raw MC: mse = 0.3 / t exactly; a method reaching mse 0.01 in 2 ms.
  std::vector<double> t = {1, 2, 4, 8, 16, 64}, e;
  for (double ti : t) e.push_back(0.3 / ti);
  double c = metrics::fitInverseLaw(t, e);
  EXPECT_NEAR(c, 0.3, 1e-12);
  // Raw needs 0.3 / 0.01 = 30 ms for that error: a 15× speed-up.
  EXPECT_NEAR(metrics::equalErrorSpeedup(c, 2.0, 0.01), 15.0, 1e-9);
  // Noisy data (±20% multiplicative, symmetric in log) still lands near c.
  std::vector<double> noisy = e;
  for (size_t i = 0; i < noisy.size(); ++i) noisy[i] *= (i % 2 ? 1.2 : 1.0 / 1.2);
  EXPECT_NEAR(metrics::fitInverseLaw(t, noisy), 0.3, 0.3 * 0.05);
  EXPECT_EQ(metrics::equalErrorSpeedup(c, 0.0, 0.01), 0.0);
}
