#include "scene/sky_tables.h"

#include <cmath>
#include <numbers>

namespace gi {
namespace {

float texelLuminance(const float* texels, uint32_t width, uint32_t channels, uint32_t x, uint32_t y) {
  const float* t = texels + (size_t(y) * width + x) * channels;
  return luminance(t[0], t[1], t[2]);
}

}  // namespace

std::vector<float> skyDistribution(const float* texels, uint32_t w, uint32_t h, uint32_t channels, float& sum) {
  std::vector<float> tables(size_t(h) + size_t(w) * h, 0.0f);
  std::vector<double> rowSums(h, 0.0);
  double total = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    const double sinTheta = std::sin(std::numbers::pi * (y + 0.5) / h);
    float* row = &tables[h + size_t(y) * w];
    double running = 0.0;
    for (uint32_t x = 0; x < w; ++x) {
      running += texelLuminance(texels, w, channels, x, y) * sinTheta;
      row[x] = float(running);
    }
    // A black row: uniform (its probability is 0 anyway).
    for (uint32_t x = 0; x < w; ++x) row[x] = running > 0.0 ? float(row[x] / running) : float(x + 1) / float(w);
    row[w - 1] = 1.0f;
    rowSums[y] = running;
    total += running;
  }
  double running = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    running += rowSums[y];
    tables[y] = total > 0.0 ? float(running / total) : float(y + 1) / float(h);
  }
  if (h > 0) tables[h - 1] = 1.0f;
  sum = float(total);
  return tables;
}

float meanLuminance(const float* texels, uint32_t w, uint32_t h, uint32_t channels) {
  double sum = 0.0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) sum += texelLuminance(texels, w, channels, x, y);
  return w && h ? float(sum / (double(w) * h)) : 0.0f;
}

}  // namespace gi
