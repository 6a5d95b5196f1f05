// Settings validation: every impossible value gets a named error that says
// which field, what value and what range.
#include <cstdio>

#include "gi/gi.h"
#include "shared/hash_grid.h"

namespace gi {
namespace {

Error outOfRangeF(const char* field, double value, double lo, double hi, bool openLow) {
  char text[256];
  std::snprintf(text, sizeof(text), "%s = %g is outside %s%g, %g]", field, value, openLow ? "(" : "[", lo, hi);
  return {ErrorCode::OutOfRange, text};
}

// Finite and inside [lo, hi] (or (lo, hi] when openLow): NaN fails every comparison.
bool inRange(double v, double lo, double hi, bool openLow) { return (openLow ? v > lo : v >= lo) && v <= hi; }

Error outOfRange(const char* field, uint64_t value, uint64_t lo, uint64_t hi) {
  char text[256];
  std::snprintf(text, sizeof(text), "%s = %llu is outside [%llu, %llu]", field, (unsigned long long)value,
                (unsigned long long)lo, (unsigned long long)hi);
  return {ErrorCode::OutOfRange, text};
}

}  // namespace

const char* methodName(Method method) {
  switch (method) {
    case Method::Raw: return "raw";
    case Method::Gif: return "gif";
    case Method::Bilateral: return "bilateral";
    case Method::Atrous: return "atrous";
    case Method::Aaf: return "aaf";
    case Method::AafAo: return "aaf_ao";
    case Method::Sspsf: return "sspsf";
    case Method::Hpsf: return "hpsf";
    case Method::Nhpsf: return "nhpsf";
    case Method::Anhpsf: return "anhpsf";
  }
  return "unknown";
}

bool methodFromName(const std::string& name, Method& out) {
  for (Method m : {Method::Raw, Method::Gif, Method::Bilateral, Method::Atrous, Method::Aaf, Method::AafAo, Method::Sspsf,
                   Method::Hpsf, Method::Nhpsf, Method::Anhpsf})
    if (name == methodName(m)) {
      out = m;
      return true;
    }
  return false;
}

Error validate(const Settings& s) {
  if (uint32_t(s.method) >= kMethodCount) return {ErrorCode::UnknownMethod, "settings.method is not a known method"};
  if (s.maxBounces < 1 || s.maxBounces > 32) return outOfRange("settings.maxBounces", s.maxBounces, 1, 32);
  if (s.russianRouletteStart < 1 || s.russianRouletteStart > 64)
    return outOfRange("settings.russianRouletteStart", s.russianRouletteStart, 1, 64);
  if (uint32_t(s.debugView) > uint32_t(DebugView::ContinuationDepth))
    return outOfRange("settings.debugView", uint32_t(s.debugView), 0, uint32_t(DebugView::ContinuationDepth));
  if (s.raw.samplesPerPixel < 1 || s.raw.samplesPerPixel > 64)
    return outOfRange("settings.raw.samplesPerPixel", s.raw.samplesPerPixel, 1, 64);
  if (s.raw.maxAccumulatedFrames < 1 || s.raw.maxAccumulatedFrames > (1u << 20))
    return outOfRange("settings.raw.maxAccumulatedFrames", s.raw.maxAccumulatedFrames, 1, 1u << 20);
  const GifSettings& g = s.gif;
  if (g.samplesPerPixel < 1 || g.samplesPerPixel > 64) return outOfRange("settings.gif.samplesPerPixel", g.samplesPerPixel, 1, 64);
  if (g.radius < 1 || g.radius > 128) return outOfRange("settings.gif.radius", g.radius, 1, 128);
  if (!inRange(g.epsilonNormal, 0, 1e6, false)) return outOfRangeF("settings.gif.epsilonNormal", g.epsilonNormal, 0, 1e6, false);
  if (!inRange(g.epsilonDepth, 0, 1e6, false)) return outOfRangeF("settings.gif.epsilonDepth", g.epsilonDepth, 0, 1e6, false);
  if (g.guidanceDimensions != 1 && g.guidanceDimensions != 3 && g.guidanceDimensions != 4)
    return {ErrorCode::OutOfRange, "settings.gif.guidanceDimensions = " + std::to_string(g.guidanceDimensions) + " is not 1, 3 or 4"};
  if (g.supersamples > 16) return outOfRange("settings.gif.supersamples", g.supersamples, 0, 16);
  const BilateralSettings& b = s.bilateral;
  if (b.samplesPerPixel < 1 || b.samplesPerPixel > 64) return outOfRange("settings.bilateral.samplesPerPixel", b.samplesPerPixel, 1, 64);
  if (b.radius < 1 || b.radius > 64) return outOfRange("settings.bilateral.radius", b.radius, 1, 64);
  if (!inRange(b.sigmaSpatial, 0, 1e4, true)) return outOfRangeF("settings.bilateral.sigmaSpatial", b.sigmaSpatial, 0, 1e4, true);
  if (!inRange(b.sigmaNormal, 0, 1e4, true)) return outOfRangeF("settings.bilateral.sigmaNormal", b.sigmaNormal, 0, 1e4, true);
  if (!inRange(b.sigmaDepth, 0, 1e4, true)) return outOfRangeF("settings.bilateral.sigmaDepth", b.sigmaDepth, 0, 1e4, true);
  const AtrousSettings& a = s.atrous;
  if (a.samplesPerPixel < 1 || a.samplesPerPixel > 64) return outOfRange("settings.atrous.samplesPerPixel", a.samplesPerPixel, 1, 64);
  if (a.iterations < 1 || a.iterations > 8) return outOfRange("settings.atrous.iterations", a.iterations, 1, 8);
  if (!inRange(a.sigmaColor, 0, 1e6, true)) return outOfRangeF("settings.atrous.sigmaColor", a.sigmaColor, 0, 1e6, true);
  if (!inRange(a.sigmaNormal, 0, 1e4, true)) return outOfRangeF("settings.atrous.sigmaNormal", a.sigmaNormal, 0, 1e4, true);
  if (!inRange(a.sigmaPosition, 0, 1e4, true)) return outOfRangeF("settings.atrous.sigmaPosition", a.sigmaPosition, 0, 1e4, true);
  const AafSettings& f = s.aaf;
  if (!inRange(f.mu, 0, 16, true)) return outOfRangeF("settings.aaf.mu", f.mu, 0, 16, true);
  if (!inRange(f.alpha, 0, 1, true)) return outOfRangeF("settings.aaf.alpha", f.alpha, 0, 1, true);
  if (f.uniformSamples != 0 && (f.uniformSamples < 16 || f.uniformSamples > 1024))
    return {ErrorCode::OutOfRange, "settings.aaf.uniformSamples = " + std::to_string(f.uniformSamples) + " is neither 0 nor in [16, 1024]"};
  if (!inRange(f.normalLimitDegrees, 0, 180, false))
    return outOfRangeF("settings.aaf.normalLimitDegrees", f.normalLimitDegrees, 0, 180, false);
  if (f.maxRadius > 1024) return outOfRange("settings.aaf.maxRadius", f.maxRadius, 0, 1024);
  const SspsfSettings& ss = s.sspsf;
  if (ss.samplesPerPixel < 1 || ss.samplesPerPixel > 64) return outOfRange("settings.sspsf.samplesPerPixel", ss.samplesPerPixel, 1, 64);
  if (ss.window < 1 || ss.window > 31 || ss.window % 2 == 0)
    return {ErrorCode::OutOfRange, "settings.sspsf.window = " + std::to_string(ss.window) + " is not an odd number in [1, 31]"};
  if (!inRange(ss.filterWidth, 0.5, 256, false)) return outOfRangeF("settings.sspsf.filterWidth", ss.filterWidth, 0.5, 256, false);
  if (!inRange(ss.normalLimitDegrees, 0, 180, false))
    return outOfRangeF("settings.sspsf.normalLimitDegrees", ss.normalLimitDegrees, 0, 180, false);
  const HpsfSettings& h = s.hpsf;
  if (h.samplesPerPixel < 1 || h.samplesPerPixel > 64) return outOfRange("settings.hpsf.samplesPerPixel", h.samplesPerPixel, 1, 64);
  if (h.capacity != 0 && (h.capacity & (h.capacity - 1)) != 0)
    return {ErrorCode::NotPowerOfTwo, "settings.hpsf.capacity = " + std::to_string(h.capacity) + " is not a power of two"};
  if (h.capacity != 0 && (h.capacity < (1u << 10) || h.capacity > (1u << 21)))
    return outOfRange("settings.hpsf.capacity", h.capacity, 1u << 10, 1u << 21);
  if (h.probeWindow < 1 || h.probeWindow > 64) return outOfRange("settings.hpsf.probeWindow", h.probeWindow, 1, 64);
  if (!inRange(h.filterWidth, 0.5, 256, false)) return outOfRangeF("settings.hpsf.filterWidth", h.filterWidth, 0.5, 256, false);
  if (!inRange(h.jitter, 0, 2, false)) return outOfRangeF("settings.hpsf.jitter", h.jitter, 0, 2, false);
  if (h.normalBits > HG_MAX_NORMAL_BITS) return outOfRange("settings.hpsf.normalBits", h.normalBits, 0, HG_MAX_NORMAL_BITS);
  if (!inRange(h.normalJitter, 0, 2, false)) return outOfRangeF("settings.hpsf.normalJitter", h.normalJitter, 0, 2, false);
  if (uint32_t(h.secondaryLod) > uint32_t(SecondaryLod::Camera))
    return outOfRange("settings.hpsf.secondaryLod", uint32_t(h.secondaryLod), 0, uint32_t(SecondaryLod::Camera));
  if (!inRange(h.clampSigma, 0, 100, false)) return outOfRangeF("settings.hpsf.clampSigma", h.clampSigma, 0, 100, false);
  if (uint32_t(h.eviction) > uint32_t(EvictionPolicy::Aging)) return outOfRange("settings.hpsf.eviction", uint32_t(h.eviction), 0, 1);
  if (h.historyFrames < 2 || h.historyFrames > 10000) return outOfRange("settings.hpsf.historyFrames", h.historyFrames, 2, 10000);
  if (h.historySamples > 1000000) return outOfRange("settings.hpsf.historySamples", h.historySamples, 0, 1000000);
  if (h.staleFrames < 1 || h.staleFrames > 100000) return outOfRange("settings.hpsf.staleFrames", h.staleFrames, 1, 100000);
  if (h.minSamples < 1 || h.minSamples > 1000000) return outOfRange("settings.hpsf.minSamples", h.minSamples, 1, 1000000);
  if (h.validationInterval > 1000) return outOfRange("settings.hpsf.validationInterval", h.validationInterval, 0, 1000);
  if (h.pathDepth < 1 || h.pathDepth > 16) return outOfRange("settings.hpsf.pathDepth", h.pathDepth, 1, 16);
  if (h.continuationDepth < 2 || h.continuationDepth > 16)
    return outOfRange("settings.hpsf.continuationDepth", h.continuationDepth, 2, 16);
  if (!inRange(h.secondaryWidthScale, 1, 16, false))
    return outOfRangeF("settings.hpsf.secondaryWidthScale", h.secondaryWidthScale, 1, 16, false);
  if (s.method == Method::Anhpsf && h.eviction == EvictionPolicy::Strict)
    return {ErrorCode::OutOfRange,
            "settings.hpsf.eviction = strict keeps cells for two frames, too short for anhpsf's transport over frames; use aging"};
  return {};
}

uint32_t hashCapacity(const HpsfSettings& s, uint32_t width, uint32_t height) {
  if (s.capacity != 0) return s.capacity;
  uint64_t want = uint64_t(width) * height * 4;
  uint32_t c = 1u << 10;
  while (c < want && c < (1u << 21)) c <<= 1;
  return c;
}

uint32_t tracedSamplesPerPixel(const Settings& s) {
  switch (s.method) {
    case Method::Raw: return s.raw.samplesPerPixel;
    case Method::Gif: return s.gif.samplesPerPixel;
    case Method::Bilateral: return s.bilateral.samplesPerPixel;
    case Method::Atrous: return s.atrous.samplesPerPixel;
    case Method::Aaf:
    case Method::AafAo: return 0;  // adaptive: chosen per pixel
    case Method::Sspsf: return s.sspsf.samplesPerPixel;
    case Method::Hpsf:
    case Method::Nhpsf:
    case Method::Anhpsf: return s.hpsf.samplesPerPixel;
  }
  return 1;
}

bool usesHashGrid(Method m) { return m == Method::Hpsf || m == Method::Nhpsf || m == Method::Anhpsf; }
bool usesScreenFilters(Method m) { return m != Method::Raw && !usesHashGrid(m); }
bool isAaf(Method m) { return m == Method::Aaf || m == Method::AafAo; }

}  // namespace gi
