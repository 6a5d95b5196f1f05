// Settings of the GI module: one struct per method, every field defaulted,
// with its unit and range. gi::validate (gi.h) names any value outside them.
#pragma once
#include <cstdint>
#include <string>

namespace gi {

enum class Method : uint32_t {
  Raw = 0,    // unfiltered paths (optionally averaged over frames)
  Gif,        // guided image filter on demodulated indirect (Bauszat et al. 2011)
  Bilateral,  // cross-bilateral baseline
  Atrous,     // edge-avoiding à-trous baseline (Dammertz et al. 2010)
  Aaf,        // axis-aligned filtering with adaptive sampling (Mehta et al. 2013)
  AafAo,      // the same machinery for ambient occlusion (reflectors radiate 1): the indirect
              // output holds occlusion, the composite AO = 1 − occlusion, both in [0,1]
};
inline constexpr uint32_t kMethodCount = 6;
const char* methodName(Method method);                      // "raw", "gif", "bilateral", "atrous", "aaf", "aaf_ao"
bool methodFromName(const std::string& name, Method& out);  // false for unknown names

enum class DebugView : uint32_t {
  None = 0,        // composite = direct + diffuse albedo × indirect
  Direct,          // direct light only (emission + first reflection)
  Indirect,        // demodulated indirect light
  Albedo,          // G-buffer base colour
  Normal,          // G-buffer normal, mapped to [0,1]
  Guidance,        // filter guidance: normal (rgb) as the guided filter sees it
  GuidanceDepth,   // filter guidance: depth channel
  FilterInOut,     // left half: noisy indirect; right half: filtered
  GifCoefficients, // guided filter: |a| (r), |b| (g) per pixel
  AafZMin,         // AAF: nearest reflector distance / scene extent
  AafZMax,         // AAF: farthest reflector distance / scene extent
  AafSamples,      // AAF: samples per pixel / 100
  AafFilterWidth,  // AAF: filter σ in pixels / 32
};

struct RawSettings {
  uint32_t samplesPerPixel = 1;        // paths per pixel per frame, [1, 64]
  bool temporalAccumulation = false;   // average frames while the camera and settings stay unchanged
  uint32_t maxAccumulatedFrames = 4096;// history cap, [1, 1<<20]; older frames fade out past it
};

struct GifSettings {
  uint32_t samplesPerPixel = 1;     // indirect paths per guide ray, [1, 64]
  uint32_t radius = 24;             // window radius in pixels, [1, 128]; cost does not depend on it
  float epsilonNormal = 0.01f;      // ridge term for normal channels, [0, 1e6] (guidance in [0,1])
  float epsilonDepth = 0.02f;       // ridge term for the depth channel, [0, 1e6]
  uint32_t guidanceDimensions = 4;  // 1 = grey normal, 3 = normal, 4 = normal + depth
  uint32_t supersamples = 0;        // extra eye rays per pixel with geometry-aware lookup, [0, 16]
};

struct BilateralSettings {
  uint32_t samplesPerPixel = 1;  // [1, 64]
  uint32_t radius = 16;          // pixels, [1, 64]; cost grows with radius²
  float sigmaSpatial = 8.0f;     // pixels, (0, 1e4]
  float sigmaNormal = 0.1f;      // on the difference of normal·0.5+0.5, (0, 1e4]
  float sigmaDepth = 0.05f;      // on the depth difference relative to the centre's depth, (0, 1e4]
};

struct AtrousSettings {
  uint32_t samplesPerPixel = 1;  // [1, 64]
  uint32_t iterations = 5;       // [1, 8]: taps up to 2^(iterations+1) pixels away
  float sigmaColor = 0.5f;       // colour stop in demodulated radiance, halved per iteration, (0, 1e6]
  float sigmaNormal = 0.1f;      // on the difference of normal·0.5+0.5, (0, 1e4]
  float sigmaPosition = 0.05f;   // world distance as a fraction of the centre's view depth, (0, 1e4]
};

struct AafSettings {
  float mu = 0.9f;                  // filter scale μ, (0, 16]: > 1 narrows filters and raises sample counts
  float alpha = 0.3f;               // pixel-space band limit α, (0, 1]
  float normalLimitDegrees = 10.0f; // neighbours whose normals differ more are not filtered in, [0, 180]
};

struct Settings {
  Method method = Method::Raw;
  RawSettings raw;
  GifSettings gif;
  BilateralSettings bilateral;
  AtrousSettings atrous;
  AafSettings aaf;                     // also used by aaf_ao
  uint32_t maxBounces = 1;             // indirect bounces B, [1, 32] (B = 0 would be direct light only)
  uint32_t russianRouletteStart = 3;   // bounce from which paths may stop early (unbiased), [1, 64]
  uint64_t rayBudget = 0;              // rays per frame; 0 = unlimited. The module lowers its sample
                                       // count (never below 1 spp) from the rays per path it last measured
  DebugView debugView = DebugView::None;
  uint32_t seed = 1;                   // random sequence; the same seed and inputs give the same frames
};

// The knob --spp and the ray budget act on: the active method's paths per pixel.
uint32_t tracedSamplesPerPixel(const Settings& settings);
bool usesScreenFilters(Method method);  // every method but raw
bool isAaf(Method method);              // aaf, aaf_ao: adaptive sample counts (tracedSamplesPerPixel is 0)

}  // namespace gi
