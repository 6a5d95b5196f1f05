#include "settings_keys.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>

namespace tools {
namespace {

using Key = SettingKey;

#define GI_KEY_U(name, meaning, field, lo, hi)                                                                   \
  {name, meaning, true, lo, hi, [](gi::Settings& s, double v) { s.field = uint32_t(v); },                      \
   [](const gi::Settings& s) { return double(s.field); }}
#define GI_KEY_F(name, meaning, field, lo, hi)                                                                   \
  {name, meaning, false, lo, hi, [](gi::Settings& s, double v) { s.field = float(v); },                        \
   [](const gi::Settings& s) { return double(s.field); }}
#define GI_KEY_B(name, meaning, field)                                                                           \
  {name, meaning, true, 0, 1, [](gi::Settings& s, double v) { s.field = v != 0; },                             \
   [](const gi::Settings& s) { return s.field ? 1.0 : 0.0; }}

}  // namespace

const std::vector<SettingKey>& settingTable() {
  static const std::vector<Key> table = {
      GI_KEY_U("bounces", "indirect bounces", maxBounces, 1, 16),
      GI_KEY_U("rr_start", "Russian roulette start bounce", russianRouletteStart, 1, 16),
      {"ray_budget", "rays per frame (0 = unlimited)", true, 0, 1e9, [](gi::Settings& s, double v) { s.rayBudget = uint64_t(v); },
       [](const gi::Settings& s) { return double(s.rayBudget); }},
      GI_KEY_U("seed", "random seed", seed, 0, 1000),
      {"view", "debug view: 0 none, 1 direct, 2 indirect, 3 albedo, 4 normal, 5 guidance, 6 guidance depth, 7 filter in|out, 8 gif coefficients, 9 aaf z_min, 10 aaf z_max, 11 aaf spp, 12 aaf filter width, 13 hash cells, 14 hash lod, 15 hash samples, 16 hash found, 17 hash occupancy, 18 continuation depth",
       true, 0, 18, [](gi::Settings& s, double v) { s.debugView = gi::DebugView(uint32_t(v)); },
       [](const gi::Settings& s) { return double(uint32_t(s.debugView)); }},
      GI_KEY_U("raw.spp", "raw: paths per pixel per frame", raw.samplesPerPixel, 1, 64),
      GI_KEY_B("raw.accumulate", "raw: 1 = temporal accumulation", raw.temporalAccumulation),
      GI_KEY_U("raw.history", "raw: accumulation cap in frames", raw.maxAccumulatedFrames, 1, 1024),
      GI_KEY_U("gif.spp", "gif: indirect paths per guide ray", gif.samplesPerPixel, 1, 64),
      GI_KEY_U("gif.radius", "gif: window radius, pixels", gif.radius, 1, 64),
      GI_KEY_F("gif.eps_normal", "gif: ridge term of the normal channels", gif.epsilonNormal, 0.0001, 1),
      GI_KEY_F("gif.eps_depth", "gif: ridge term of the depth channel", gif.epsilonDepth, 0.0001, 1),
      GI_KEY_U("gif.dims", "gif: guidance dimensions 1, 3 or 4", gif.guidanceDimensions, 1, 4),
      GI_KEY_U("gif.supersamples", "gif: extra eye rays per pixel", gif.supersamples, 0, 16),
      GI_KEY_U("bilateral.spp", "bilateral: paths per pixel", bilateral.samplesPerPixel, 1, 64),
      GI_KEY_U("bilateral.radius", "bilateral: radius, pixels", bilateral.radius, 1, 32),
      GI_KEY_F("bilateral.sigma_spatial", "bilateral: spatial sigma, pixels", bilateral.sigmaSpatial, 0.5, 32),
      GI_KEY_F("bilateral.sigma_normal", "bilateral: normal sigma", bilateral.sigmaNormal, 0.01, 1),
      GI_KEY_F("bilateral.sigma_depth", "bilateral: relative depth sigma", bilateral.sigmaDepth, 0.001, 1),
      GI_KEY_U("atrous.spp", "atrous: paths per pixel", atrous.samplesPerPixel, 1, 64),
      GI_KEY_U("atrous.iterations", "atrous: wavelet iterations", atrous.iterations, 1, 8),
      GI_KEY_F("atrous.sigma_color", "atrous: colour sigma", atrous.sigmaColor, 0.01, 10),
      GI_KEY_F("atrous.sigma_normal", "atrous: normal sigma", atrous.sigmaNormal, 1, 256),
      GI_KEY_F("atrous.sigma_position", "atrous: position sigma, fraction of depth", atrous.sigmaPosition, 0.001, 1),
      GI_KEY_F("aaf.mu", "aaf, aaf_ao: filter scale mu", aaf.mu, 0.1, 8),
      GI_KEY_F("aaf.alpha", "aaf, aaf_ao: pixel band limit alpha", aaf.alpha, 0.05, 2),
      GI_KEY_F("aaf.normal_limit", "aaf, aaf_ao: normal rejection angle, degrees", aaf.normalLimitDegrees, 0, 90),
      GI_KEY_U("aaf.uniform", "aaf, aaf_ao: 0 = adaptive, N = N samples in every pixel", aaf.uniformSamples, 0, 1024),
      GI_KEY_U("aaf.max_radius", "aaf, aaf_ao: filter radius cap, pixels (0 = 3 sigma)", aaf.maxRadius, 0, 1024),
      GI_KEY_U("sspsf.spp", "sspsf: paths per pixel", sspsf.samplesPerPixel, 1, 64),
      GI_KEY_U("sspsf.window", "sspsf: odd window side, pixels", sspsf.window, 1, 31),
      GI_KEY_F("sspsf.width", "sspsf: filter width, pixels", sspsf.filterWidth, 0.5, 256),
      GI_KEY_F("sspsf.normal_limit", "sspsf: normal rejection angle, degrees", sspsf.normalLimitDegrees, 0, 180),
      GI_KEY_U("hpsf.spp", "hpsf: paths per pixel", hpsf.samplesPerPixel, 1, 64),
      GI_KEY_U("hpsf.capacity", "hpsf: cells, power of two (0 = auto)", hpsf.capacity, 0, 2097152),
      GI_KEY_U("hpsf.probe", "hpsf: probe window, slots", hpsf.probeWindow, 1, 64),
      GI_KEY_F("hpsf.width", "hpsf: filter width, pixels", hpsf.filterWidth, 0.5, 256),
      GI_KEY_F("hpsf.jitter", "hpsf: jitter, cells", hpsf.jitter, 0, 2),
      GI_KEY_U("hpsf.normal_bits", "hpsf: normal bins 2^b in all", hpsf.normalBits, 0, 6),
      GI_KEY_F("hpsf.normal_jitter", "hpsf: normal jitter, bins", hpsf.normalJitter, 0, 2),
      {"hpsf.secondary_lod", "hpsf: nhpsf/anhpsf secondary LOD travel: 0 segment (thesis), 1 path, 2 camera", true, 0, 2,
       [](gi::Settings& s, double v) { s.hpsf.secondaryLod = gi::SecondaryLod(uint32_t(v)); },
       [](const gi::Settings& s) { return double(uint32_t(s.hpsf.secondaryLod)); }},
      GI_KEY_B("hpsf.stochastic_lod", "hpsf: 1 = stochastic LOD", hpsf.stochasticLod),
      GI_KEY_F("hpsf.clamp", "hpsf: outlier clamp k (0 = off)", hpsf.clampSigma, 0, 100),
      {"hpsf.aging", "hpsf: 1 = aging eviction, 0 = strict", true, 0, 1,
       [](gi::Settings& s, double v) { s.hpsf.eviction = v != 0 ? gi::EvictionPolicy::Aging : gi::EvictionPolicy::Strict; },
       [](const gi::Settings& s) { return s.hpsf.eviction == gi::EvictionPolicy::Aging ? 1.0 : 0.0; }},
      GI_KEY_U("hpsf.history", "hpsf: history frames (aging)", hpsf.historyFrames, 2, 1000),
      GI_KEY_U("hpsf.history_samples", "hpsf: nhpsf/anhpsf history samples (aging; 0 = no limit)", hpsf.historySamples, 0, 1000000),
      GI_KEY_U("hpsf.stale", "hpsf: stale frames before eviction (aging)", hpsf.staleFrames, 1, 1000),
      GI_KEY_U("hpsf.min_samples", "hpsf: minimum samples to use a cell", hpsf.minSamples, 1, 1000),
      GI_KEY_U("hpsf.validation", "hpsf: re-trace each cell's probe every N frames (aging; 0 = off)", hpsf.validationInterval, 0, 64),
      GI_KEY_U("hpsf.path_depth", "hpsf: nhpsf path segments per frame", hpsf.pathDepth, 1, 16),
      GI_KEY_U("hpsf.continuation_depth", "hpsf: anhpsf longest continued path, segments", hpsf.continuationDepth, 2, 16),
      GI_KEY_F("hpsf.secondary_width", "hpsf: nhpsf/anhpsf cell width scale after the first vertex", hpsf.secondaryWidthScale, 1, 16),
  };
  return table;
}

#undef GI_KEY_U
#undef GI_KEY_F
#undef GI_KEY_B

gi::Method keyOwner(gi::Method m) {
  if (m == gi::Method::AafAo) return gi::Method::Aaf;
  if (gi::usesHashGrid(m)) return gi::Method::Hpsf;
  return m;
}

bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error) {
  size_t eq = assignment.find('=');
  std::string name = assignment.substr(0, eq);
  for (const Key& k : settingTable()) {
    if (name != k.name) continue;
    if (eq == std::string::npos) {
      error = "setting '" + name + "' needs a value (" + name + "=N)";
      return false;
    }
    std::string value = assignment.substr(eq + 1);
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(value.c_str(), &end);
    bool whole = v >= 0.0 && v <= 1.8e19 && std::floor(v) == v;
    if (value.empty() || *end != '\0' || errno != 0 || !std::isfinite(v) || (k.integer && !whole)) {
      error = "setting '" + name + "' must be " + (k.integer ? "a whole number" : "a finite number") + ", not '" + value + "'";
      return false;
    }
    k.set(settings, v);
    return true;
  }
  error = "unknown setting '" + name + "'; known:";
  for (const Key& k : settingTable()) error += std::string(" ") + k.name;
  return false;
}

std::vector<std::string> settingKeys() {
  std::vector<std::string> out;
  for (const Key& k : settingTable()) out.push_back(std::string(k.name) + "  (" + k.meaning + ")");
  return out;
}

std::vector<const char*> methodNames() {
  std::vector<const char*> names;
  for (uint32_t m = 0; m < gi::kMethodCount; ++m) names.push_back(gi::methodName(gi::Method(m)));
  return names;
}

std::string methodList() {
  std::string list;
  for (const char* name : methodNames()) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

}  // namespace tools
