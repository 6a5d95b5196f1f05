// Settings validation: every impossible value gets a named error that says
// which field, what value and what range.
#include <algorithm>

#include "gi/catalogue.h"
#include "gi/gi.h"
#include "shared/hash_grid.h"

namespace gi {

Error validate(const Settings& s) {
  if (uint32_t(s.method) >= kMethodCount) return {ErrorCode::UnknownMethod, "settings.method is not a known method"};
  // Every field against its catalogue range (NaN fails every comparison).
  for (const SettingInfo& k : settingCatalogue()) {
    const double v = k.get(s);
    if (!inRange(k, v)) return {ErrorCode::OutOfRange, outOfRangeText(k, v)};
  }
  // What a range cannot say.
  if (s.gif.guidanceDimensions == 2)
    return {ErrorCode::OutOfRange, "settings.gif.guidanceDimensions = 2 is not 1, 3 or 4"};
  if (s.aaf.uniformSamples != 0 && s.aaf.uniformSamples < 16)
    return {ErrorCode::OutOfRange, "settings.aaf.uniformSamples = " + std::to_string(s.aaf.uniformSamples) +
                                       " is neither 0 nor in [16, 1024]"};
  if (s.sspsf.window % 2 == 0)
    return {ErrorCode::OutOfRange,
            "settings.sspsf.window = " + std::to_string(s.sspsf.window) + " is not an odd number in [1, 31]"};
  const HpsfSettings& h = s.hpsf;
  if (h.capacity != 0 && (h.capacity & (h.capacity - 1)) != 0)
    return {ErrorCode::NotPowerOfTwo,
            "settings.hpsf.capacity = " + std::to_string(h.capacity) + " is not a power of two"};
  if (h.capacity != 0 && h.capacity < (1u << 10))
    return {ErrorCode::OutOfRange, "settings.hpsf.capacity = " + std::to_string(h.capacity) +
                                       " is neither 0 nor in [1024, " + std::to_string(kMaxHashCapacity) + "]"};
  if (s.method == Method::Anhpsf && h.eviction == EvictionPolicy::Strict)
    return {ErrorCode::OutOfRange,
            "settings.hpsf.eviction = strict keeps cells for two frames, too short for anhpsf's transport over frames; "
            "use aging"};
  return {};
}

namespace {

// The cells nhpsf's and anhpsf's paths keep live, from the vertices a pixel's path reaches (its
// segments): nhpsf at its defaults on Sponza kept 0.16 cells live a vertex at 160×90, 0.13 at 320×180 and
// 0.09 at 1920×1080 (RESULTS, "The n-methods' map"). A third of a cell a vertex keeps the map at about
// half load or less, where the probe window finds every key a slot; full, it turns samples away, and
// which ones depends on the order the threads ran in. Not the samples a pixel: more of them a frame reach
// the same cells sooner, and the ray budget changes them every frame, which must not rebuild the map.
double nMethodCells(const Settings& s, uint32_t width, uint32_t height) {
  const uint32_t segments = s.method == Method::Nhpsf ? s.hpsf.pathDepth : s.hpsf.continuationDepth;
  return double(width) * height * segments / 3.0;
}

bool nMethod(Method m) { return m == Method::Nhpsf || m == Method::Anhpsf; }

// The n-methods' map grows to what their vertices need up to 2^19 cells (what the quarter cell a pixel gives
// at 1920×1080: issue 30's memory, docs/RESULTS.md's memory table); beyond, their later cells widen instead.
constexpr double kNMethodCellsCap = double(1u << 19);

// anhpsf's walks keep the fed cell's index hash mod 2^HG_WALK_INDEX_BITS: all the probes read of it up to
// the largest map.
static_assert(kMaxHashCapacity <= (1u << gpu::HG_WALK_INDEX_BITS), "a walk's index bits cover the map");

}  // namespace

uint32_t hashCapacity(const Settings& s, uint32_t width, uint32_t height) {
  if (s.hpsf.capacity != 0) return s.hpsf.capacity;
  // A quarter of a cell per pixel: a 60-frame Sponza walk at 1920×1080 (default width 16, aging) had 121k
  // cells live (0.058 per pixel), 23% of this; at 2^18 cells (46% full) inserts began to fail (RESULTS).
  double want = double(width) * height / 4.0;
  if (nMethod(s.method)) want = std::max(want, std::min(nMethodCells(s, width, height), kNMethodCellsCap));
  uint32_t c = 1u << 10;
  while (c < want && c < kMaxHashCapacity) c <<= 1;
  return c;
}

float hashSecondaryWidth(const Settings& s, uint32_t width, uint32_t height) {
  const HpsfSettings& h = s.hpsf;
  if (!nMethod(s.method)) return h.secondaryWidthScale;
  // Where the map is smaller than the vertices need (its cap, or a capacity set by hand), the cells after
  // the first vertex widen: widened 4× they kept 29% of the live cells at 160×90 (2×: 46%), so the width
  // doubles until the need over the width fits the map.
  const double need = nMethodCells(s, width, height), capacity = hashCapacity(s, width, height);
  float fit = 1.0f;
  while (need > capacity * fit && fit < 16.0f) fit *= 2.0f;
  return std::max(h.secondaryWidthScale, fit);
}

namespace {

// The active method's paths-per-pixel field (const or not), or null for AAF (adaptive: chosen per pixel).
template <typename SettingsT>
auto samplesPerPixelField(SettingsT& s) -> decltype(&s.raw.samplesPerPixel) {
  switch (s.method) {
    case Method::Raw: return &s.raw.samplesPerPixel;
    case Method::Gif: return &s.gif.samplesPerPixel;
    case Method::Bilateral: return &s.bilateral.samplesPerPixel;
    case Method::Atrous: return &s.atrous.samplesPerPixel;
    case Method::Aaf:
    case Method::AafAo: return nullptr;
    case Method::Sspsf: return &s.sspsf.samplesPerPixel;
    case Method::Hpsf:
    case Method::Nhpsf:
    case Method::Anhpsf: return &s.hpsf.samplesPerPixel;
    case Method::Svgf: return &s.svgf.samplesPerPixel;
  }
  return nullptr;
}

}  // namespace

uint32_t tracedSamplesPerPixel(const Settings& s) {
  const uint32_t* field = samplesPerPixelField(s);
  return field ? *field : 0u;
}

void setTracedSamplesPerPixel(Settings& s, uint32_t spp) {
  if (uint32_t* field = samplesPerPixelField(s)) *field = spp;
}

bool usesHashGrid(Method m) { return m == Method::Hpsf || m == Method::Nhpsf || m == Method::Anhpsf; }
bool usesScreenFilters(Method m) { return m != Method::Raw && m != Method::Svgf && !usesHashGrid(m); }
bool isAaf(Method m) { return m == Method::Aaf || m == Method::AafAo; }
bool usesTemporalReprojection(const Settings& s) {
  switch (s.method) {
    // raw.accumulate keeps its own still-camera mean in the same history images.
    case Method::Raw: return s.raw.temporalReprojection && !s.raw.temporalAccumulation;
    case Method::Gif: return s.gif.temporalReprojection;
    case Method::Bilateral: return s.bilateral.temporalReprojection;
    case Method::Atrous: return s.atrous.temporalReprojection;
    case Method::Sspsf: return s.sspsf.temporalReprojection;
    case Method::Hpsf:
    case Method::Nhpsf:
    case Method::Anhpsf: return s.hpsf.temporalDirect;  // direct light only: the map caches the indirect
    case Method::Svgf: return true;                     // its first half
    default: return false;                              // AAF samples adaptively per frame
  }
}

}  // namespace gi
