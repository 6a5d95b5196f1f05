// The sky map's importance-sampling tables (shaders/module/sky.glsl reads them).
#pragma once
#include <cstdint>
#include <vector>

namespace gi {

// Rec. 709 luminance of linear rgb.
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

// `texels`: width × height texels of `channels` floats (rgb first), row 0 at
// the top (θ = 0). Returns H cumulative row probabilities, then per row W
// cumulative column probabilities, each ending at 1; texels weighted by
// luminance × sin θ at the row's centre. `sum` gets Σ of the weights (0: the
// map is black).
std::vector<float> skyDistribution(const float* texels, uint32_t width, uint32_t height, uint32_t channels, float& sum);

// Mean luminance of the texels (each texel alike, not by solid angle).
float meanLuminance(const float* texels, uint32_t width, uint32_t height, uint32_t channels);

}  // namespace gi
