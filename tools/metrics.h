// Image error metrics against a reference, and the equal-error fit used to
// compare methods at the same accuracy. All images are linear RGB floats.
#pragma once
#include <span>

#include "image_io.h"

namespace metrics {

struct ImageError {
  double mse = 0.0;     // mean over pixels and channels of (x − ref)²
  double relMse = 0.0;  // mean of (x − ref)² / (ref² + 0.01): scale-free, tames dark pixels
  double psnr = 0.0;    // 10·log10(1 / mse), peak 1.0 on linear radiance (∞ for identical images)
  double ssim = 0.0;    // mean SSIM of luminance clamped to [0,1], 11×11 Gaussian window (σ = 1.5)
  double energy = 1.0;  // mean luminance over the reference's (1 = no bias in total light; 1 when both are black)
};

ImageError compare(const engine::FloatImage& image, const engine::FloatImage& reference);

double mse(const engine::FloatImage& a, const engine::FloatImage& b);
double relMse(const engine::FloatImage& a, const engine::FloatImage& b);
double psnrFromMse(double mse);
// Rec. 709 luminance of pixel (x, y); the value itself for one-channel images.
double luminance(const engine::FloatImage& image, uint32_t x, uint32_t y);
double energyRatio(const engine::FloatImage& image, const engine::FloatImage& reference);
double ssim(const engine::FloatImage& a, const engine::FloatImage& b);

// Raw Monte Carlo error falls as MSE = c / t (t ∝ spp). Least-squares fit of
// log c over the samples (t_i, mse_i); both spans must be the same length ≥ 1.
double fitInverseLaw(std::span<const double> times, std::span<const double> errors);
// How much longer raw MC needs than a method to reach the method's error:
// (c / methodError) / methodTime.
double equalErrorSpeedup(double c, double methodTimeMs, double methodError);

}  // namespace metrics
