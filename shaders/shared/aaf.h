// Axis-aligned filtering (Mehta et al. 2013): the per-pixel filter width and
// sample count, shared verbatim by C++ (tests) and GLSL (aaf_*.comp), and the
// passes' interface. Distances in metres; β is a world-space Gaussian σ.
#ifndef GI_AAF_H
#define GI_AAF_H
#include "gpu_common.h"
#include "gi_filters.h"  // FilterOutputEncoding

GPU_NAMESPACE_BEGIN

#define AAF_OMEGA_DIFFUSE 2.8            // Ω_h^max for a Lambertian receiver (eq. 18)
#define AAF_GAMMA_DIFFUSE 0.4            // γ for the cosine lobe (§4.3)
#define AAF_INITIAL_SAMPLES 16u          // pass 1: 4×4 stratified cosine rays
#define AAF_ZMIN_FRACTION 0.02           // z_min ≥ 2% of the scene's largest dimension
#define AAF_MAX_SAMPLES_PER_MU 100.0     // n ≤ 100·μ
#define AAF_MIN_COS_VIEW 0.01            // foreshortening is capped at 100× a pixel's frontal size

// Ω_h^max for a Blinn-Phong receiver of exponent m (eq. 18).
GPU_FN float aafOmegaGlossy(float m) { return 3.6f + 0.084f * m; }
// The Blinn-Phong exponent equivalent to a GGX lobe of width α = roughness²
// (Walter et al. 2007: m = 2/α² − 2), at least 1 so γ stays finite.
GPU_FN float aafPhongExponent(float ggxAlpha) { return max(2.0f / (ggxAlpha * ggxAlpha) - 2.0f, 1.0f); }
// γ for a Blinn-Phong lobe: arccos(c^(1/m)) / (π/2), c = cos(π/4) (§4.3).
GPU_FN float aafGammaGlossy(float m) { return acos(pow(0.70710678f, 1.0f / m)) / 1.57079633f; }

GPU_FN float aafClampZMin(float zMin, float sceneExtent) { return max(zMin, float(AAF_ZMIN_FRACTION) * sceneExtent); }

// d, the world-space size of a pixel on the receiver (eq. 15, footnote 7:
// "accounts for perspective effects and foreshortening"): the pixel's frontal
// size at view depth `viewZ` (pixelScale metres per metre), divided by the
// cosine between the surface normal and the direction to the camera.
GPU_FN float aafPixelFootprint(float viewZ, float pixelScale, float cosView) {
  return viewZ * pixelScale / max(abs(cosView), float(AAF_MIN_COS_VIEW));
}

// Stratification of `count` samples over the unit square (§5, "stratified
// and importance sampled"): a side × side grid with side = ⌈√count⌉, and
// sample i takes cell (a·i + offset) mod side², a = 2·side + 1 (coprime with
// side², so the map is a permutation: no two samples share a cell). Returns
// the cell's corner in [0, 1)²; the caller adds a random point inside it
// times 1/side.
GPU_FN vec2 aafStratum(uint i, uint count, uint offset, GPU_OUT(float) cellSize) {
  uint side = uint(ceil(sqrt(float(max(count, 1u)))));
  while (side * side < count) side += 1u;  // √ rounding
  uint cells = side * side;
  uint cell = ((2u * side + 1u) * i + offset) % cells;
  cellSize = 1.0f / float(side);
  return vec2(float(cell % side), float(cell / side)) * cellSize;
}

// Ω_x^r = μ·min(Ω_h^max / z_min, α / d) (eq. 15); d = world size of a pixel.
GPU_FN float aafBandwidth(float mu, float omegaMax, float zMin, float alpha, float d) {
  return mu * min(omegaMax / zMin, alpha / d);
}
// β = 2 / Ω_x^r: the world-space standard deviation of the filter (eq. 16).
GPU_FN float aafBeta(float mu, float omegaMax, float zMin, float alpha, float d) {
  return 2.0f / aafBandwidth(mu, omegaMax, zMin, alpha, d);
}
// n(μ) = γ·(μ·Ω·√A_p/z_min + α)²·Ω²·(1 + μ·z_max/z_min)², A_p = d² (eq. 21),
// clamped to [16, 100·μ] (the upper clamp never below 16).
GPU_FN float aafSamples(float mu, float omegaMax, float gamma, float zMin, float zMax, float alpha, float d) {
  float a = mu * omegaMax * d / zMin + alpha;
  float b = 1.0f + mu * zMax / zMin;
  float n = gamma * a * a * omegaMax * omegaMax * b * b;
  return clamp(n, float(AAF_INITIAL_SAMPLES), max(float(AAF_INITIAL_SAMPLES), float(AAF_MAX_SAMPLES_PER_MU) * mu));
}

struct AafPush {
  float mu;             // filter scale μ (> 1 converges)
  float alpha;          // pixel-space band limit α
  float sceneExtent;    // metres
  uint seed;
  uint ambientOcclusion;// 1: reflectors radiate 1, the output is AO in [0,1]
  uint sampleBudget;    // pass 2: total samples the frame may take (0 = unlimited)
  uint maxBounces;      // indirect bounces
  uint russianRouletteStart;
  uint uniformSamples;  // 0: n(μ) per pixel; otherwise this many samples everywhere
  uint glossy;          // 1: the scene has glossy materials; their receivers get a separately filtered specular term
  uint pad1;
  uint pad2;
};
GPU_ASSERT_SIZE(AafPush, 48);

struct AafFilterPush {
  uint vertical;        // 0: along rows (input → temp); 1: along columns (temp → output)
  float cosNormalLimit; // neighbours whose normals differ by more than the limit angle are rejected
  float pixelScale;     // world size of a pixel per metre of view depth: 2·tan(fovY/2) / height
  uint maxRadius;       // pixels; the Gaussian is cut at 3σ or here (0: at 3σ, within the image)
  FilterOutputEncoding encoding;  // of the output image
  float positionScale;  // metres per unit of the position image (the module's: the scene extent; β is in metres)
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(AafFilterPush, 36);

GPU_NAMESPACE_END
#endif
