#include "image_io.h"

#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "stb_image_write.h"

namespace engine {
namespace {

std::string extensionOf(const std::string& path) {
  size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// RGB (or grey) view of any channel count: grey is replicated, alpha dropped.
float channelOrGrey(const FloatImage& img, uint32_t x, uint32_t y, uint32_t c) {
  return img.at(x, y, img.channels >= 3 ? c : 0);
}

bool writePfm(const std::string& path, const FloatImage& img, std::string& error) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), std::fclose);
  if (!f) {
    error = path + ": cannot open for writing";
    return false;
  }
  bool grey = img.channels == 1;
  std::fprintf(f.get(), "%s\n%u %u\n-1.0\n", grey ? "Pf" : "PF", img.width, img.height);
  std::vector<float> row(size_t(img.width) * (grey ? 1 : 3));
  for (uint32_t y = img.height; y-- > 0;) {  // PFM stores the bottom row first
    for (uint32_t x = 0; x < img.width; ++x)
      for (uint32_t c = 0; c < (grey ? 1u : 3u); ++c) row[size_t(x) * (grey ? 1 : 3) + c] = channelOrGrey(img, x, y, c);
    if (std::fwrite(row.data(), sizeof(float), row.size(), f.get()) != row.size()) {
      error = path + ": write failed";
      return false;
    }
  }
  return true;
}

bool readPfm(const std::string& path, FloatImage& img, std::string& error) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!f) {
    error = path + ": cannot open";
    return false;
  }
  char magic[3] = {0};
  unsigned w = 0, h = 0;
  float scale = 0.0f;
  if (std::fscanf(f.get(), "%2s %u %u %f", magic, &w, &h, &scale) != 4 ||
      (std::strcmp(magic, "PF") && std::strcmp(magic, "Pf")) || w == 0 || h == 0 || w > 65536 || h > 65536 ||
      scale == 0.0f) {
    error = path + ": not a valid PFM header";
    return false;
  }
  std::fgetc(f.get());
  uint32_t c = magic[1] == 'F' ? 3 : 1;
  img = FloatImage(w, h, c);
  std::vector<float> row(size_t(w) * c);
  for (uint32_t y = h; y-- > 0;) {
    if (std::fread(row.data(), sizeof(float), row.size(), f.get()) != row.size()) {
      error = path + ": file ends before its pixels do";
      return false;
    }
    std::memcpy(&img.pixels[size_t(y) * w * c], row.data(), row.size() * sizeof(float));
  }
  if (scale > 0.0f) {  // big-endian data
    for (float& v : img.pixels) {
      uint32_t u;
      std::memcpy(&u, &v, 4);
      u = __builtin_bswap32(u);
      std::memcpy(&v, &u, 4);
    }
  }
  return true;
}

}  // namespace

float halfToFloat(uint16_t h) {
  uint32_t sign = (h >> 15) & 1, exp = (h >> 10) & 31, mant = h & 1023;
  float v = exp == 0    ? std::ldexp(float(mant), -24)
            : exp == 31 ? (mant ? std::nanf("") : INFINITY)
                        : std::ldexp(float(mant | 1024), int(exp) - 25);
  return sign ? -v : v;
}

float linearToSrgb(float v) {
  if (!(v > 0.0f)) return 0.0f;  // also maps NaN to black
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

bool writeImage(const std::string& path, const FloatImage& img, std::string& error) {
  std::string ext = extensionOf(path);
  if (ext == "pfm") return writePfm(path, img, error);
  if (ext == "exr") {
    // tinyexr wants 1, 3 or 4 channels; write RGB(A) as stored.
    const char* err = nullptr;
    int channels = img.channels == 2 ? 3 : int(img.channels);
    std::vector<float> data;
    const float* src = img.pixels.data();
    if (img.channels == 2) {
      data.resize(size_t(img.width) * img.height * 3, 0.0f);
      for (size_t i = 0; i < size_t(img.width) * img.height; ++i) {
        data[3 * i] = img.pixels[2 * i];
        data[3 * i + 1] = img.pixels[2 * i + 1];
      }
      src = data.data();
    }
    if (SaveEXR(src, int(img.width), int(img.height), channels, 0, path.c_str(), &err) != TINYEXR_SUCCESS) {
      error = path + ": " + (err ? err : "EXR write failed");
      if (err) FreeEXRErrorMessage(err);
      return false;
    }
    return true;
  }
  if (ext == "png") {
    std::vector<uint8_t> bytes(size_t(img.width) * img.height * 3);
    for (uint32_t y = 0; y < img.height; ++y)
      for (uint32_t x = 0; x < img.width; ++x)
        for (uint32_t c = 0; c < 3; ++c)
          bytes[(size_t(y) * img.width + x) * 3 + c] =
              uint8_t(std::lround(255.0f * linearToSrgb(channelOrGrey(img, x, y, c))));
    if (!stbi_write_png(path.c_str(), int(img.width), int(img.height), 3, bytes.data(), int(img.width) * 3)) {
      error = path + ": PNG write failed";
      return false;
    }
    return true;
  }
  error = path + ": unknown image extension '." + ext + "' (use .exr, .pfm or .png)";
  return false;
}

bool readImage(const std::string& path, FloatImage& img, std::string& error) {
  std::string ext = extensionOf(path);
  if (ext == "pfm") return readPfm(path, img, error);
  if (ext == "exr") {
    float* rgba = nullptr;
    int w = 0, h = 0;
    const char* err = nullptr;
    if (LoadEXR(&rgba, &w, &h, path.c_str(), &err) != TINYEXR_SUCCESS) {
      error = path + ": " + (err ? err : "EXR read failed");
      if (err) FreeEXRErrorMessage(err);
      return false;
    }
    img = FloatImage(uint32_t(w), uint32_t(h), 3);
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int c = 0; c < 3; ++c) img.pixels[3 * i + c] = rgba[4 * i + c];
    std::free(rgba);
    return true;
  }
  error = path + ": cannot read '." + ext + "' images (use .exr or .pfm)";
  return false;
}

}  // namespace engine
