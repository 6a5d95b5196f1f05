// CPU-side float images and their files: EXR (linear, fp32), PFM (linear) and
// PNG (sRGB-encoded, clamped, for viewing). Errors name the file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace engine {

struct FloatImage {
  uint32_t width = 0, height = 0, channels = 3;
  std::vector<float> pixels;  // row-major, top row first, `channels` floats per pixel

  FloatImage() = default;
  FloatImage(uint32_t w, uint32_t h, uint32_t c) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, 0.0f) {}
  float& at(uint32_t x, uint32_t y, uint32_t c) { return pixels[(size_t(y) * width + x) * channels + c]; }
  float at(uint32_t x, uint32_t y, uint32_t c) const { return pixels[(size_t(y) * width + x) * channels + c]; }
};

// Chooses the format from the extension (.exr, .pfm, .png).
bool writeImage(const std::string& path, const FloatImage& image, std::string& error);
bool readImage(const std::string& path, FloatImage& image, std::string& error);  // .exr or .pfm

float linearToSrgb(float linear);
float halfToFloat(uint16_t half);  // IEEE 754 binary16, for reading rgba16f/rg16f images back

}  // namespace engine
