#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace metrics {

double luminance(const engine::FloatImage& img, uint32_t x, uint32_t y) {
  return img.channels >= 3 ? 0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2)
                           : img.at(x, y, 0);
}

namespace {

std::vector<double> clampedLuminance(const engine::FloatImage& img) {
  std::vector<double> out(size_t(img.width) * img.height);
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) {
      double l = luminance(img, x, y);
      out[size_t(y) * img.width + x] = std::isfinite(l) ? std::clamp(l, 0.0, 1.0) : 0.0;
    }
  return out;
}

// One axis of a separable Gaussian (σ = 1.5, radius 5), renormalised at the borders.
std::vector<double> blurAxis(const std::vector<double>& v, uint32_t w, uint32_t h, bool vertical) {
  constexpr int kRadius = 5;
  constexpr double kSigma = 1.5;
  double weights[2 * kRadius + 1];
  for (int i = -kRadius; i <= kRadius; ++i) weights[i + kRadius] = std::exp(-0.5 * i * i / (kSigma * kSigma));
  std::vector<double> out(v.size());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      double sum = 0.0, norm = 0.0;
      for (int i = -kRadius; i <= kRadius; ++i) {
        int xx = int(x) + (vertical ? 0 : i), yy = int(y) + (vertical ? i : 0);
        if (xx < 0 || xx >= int(w) || yy < 0 || yy >= int(h)) continue;
        sum += weights[i + kRadius] * v[size_t(yy) * w + xx];
        norm += weights[i + kRadius];
      }
      out[size_t(y) * w + x] = sum / norm;
    }
  return out;
}

std::vector<double> blur(const std::vector<double>& v, uint32_t w, uint32_t h) {
  return blurAxis(blurAxis(v, w, h, false), w, h, true);
}

}  // namespace

double mse(const engine::FloatImage& a, const engine::FloatImage& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    double d = double(a.pixels[i]) - double(b.pixels[i]);
    sum += d * d;
  }
  return a.pixels.empty() ? 0.0 : sum / double(a.pixels.size());
}

double relMse(const engine::FloatImage& a, const engine::FloatImage& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    double r = b.pixels[i], d = double(a.pixels[i]) - r;
    sum += d * d / (r * r + 0.01);
  }
  return a.pixels.empty() ? 0.0 : sum / double(a.pixels.size());
}

double energyRatio(const engine::FloatImage& image, const engine::FloatImage& reference) {
  auto meanLuminance = [](const engine::FloatImage& img) {
    double sum = 0.0;
    for (uint32_t y = 0; y < img.height; ++y)
      for (uint32_t x = 0; x < img.width; ++x) sum += luminance(img, x, y);
    return sum;
  };
  double a = meanLuminance(image), b = meanLuminance(reference);
  return b > 0.0 ? a / b : (a > 0.0 ? std::numeric_limits<double>::infinity() : 1.0);
}

double psnrFromMse(double m) { return m > 0.0 ? 10.0 * std::log10(1.0 / m) : std::numeric_limits<double>::infinity(); }

double ssim(const engine::FloatImage& a, const engine::FloatImage& b) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;  // (k·L)² with L = 1
  uint32_t w = a.width, h = a.height;
  std::vector<double> x = clampedLuminance(a), y = clampedLuminance(b);
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  std::vector<double> mx = blur(x, w, h), my = blur(y, w, h), sxx = blur(xx, w, h), syy = blur(yy, w, h),
                      sxy = blur(xy, w, h);
  double sum = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
    sum += ((2 * mx[i] * my[i] + c1) * (2 * cxy + c2)) / ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
  }
  return x.empty() ? 1.0 : sum / double(x.size());
}

ImageError compare(const engine::FloatImage& image, const engine::FloatImage& reference) {
  ImageError e;
  e.mse = mse(image, reference);
  e.relMse = relMse(image, reference);
  e.psnr = psnrFromMse(e.mse);
  e.ssim = ssim(image, reference);
  e.energy = energyRatio(image, reference);
  return e;
}

double fitInverseLaw(std::span<const double> times, std::span<const double> errors) {
  // log mse = log c − log t  ⇒  log c = mean(log mse + log t).
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < times.size() && i < errors.size(); ++i) {
    if (!(times[i] > 0.0) || !(errors[i] > 0.0)) continue;
    sum += std::log(errors[i]) + std::log(times[i]);
    ++n;
  }
  return n ? std::exp(sum / double(n)) : 0.0;
}

double equalErrorSpeedup(double c, double methodTimeMs, double methodError) {
  if (!(c > 0.0) || !(methodTimeMs > 0.0) || !(methodError > 0.0)) return 0.0;
  return (c / methodError) / methodTimeMs;
}

}  // namespace metrics
