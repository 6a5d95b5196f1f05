#include "settings_keys.h"

#include <cerrno>
#include <cstdlib>
#include <functional>

namespace tools {
namespace {

struct Key {
  const char* name;
  const char* meaning;
  std::function<void(gi::Settings&, uint64_t)> set;
};

const std::vector<Key>& keys() {
  static const std::vector<Key> table = {
      {"raw.spp", "raw: paths per pixel per frame", [](gi::Settings& s, uint64_t v) { s.raw.samplesPerPixel = uint32_t(v); }},
      {"raw.accumulate", "raw: 1 = temporal accumulation", [](gi::Settings& s, uint64_t v) { s.raw.temporalAccumulation = v != 0; }},
      {"raw.history", "raw: accumulation cap in frames", [](gi::Settings& s, uint64_t v) { s.raw.maxAccumulatedFrames = uint32_t(v); }},
      {"bounces", "indirect bounces", [](gi::Settings& s, uint64_t v) { s.maxBounces = uint32_t(v); }},
      {"rr_start", "Russian roulette start bounce", [](gi::Settings& s, uint64_t v) { s.russianRouletteStart = uint32_t(v); }},
      {"ray_budget", "rays per frame (0 = unlimited)", [](gi::Settings& s, uint64_t v) { s.rayBudget = v; }},
      {"seed", "random seed", [](gi::Settings& s, uint64_t v) { s.seed = uint32_t(v); }},
  };
  return table;
}

}  // namespace

bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error) {
  size_t eq = assignment.find('=');
  std::string name = assignment.substr(0, eq);
  for (const Key& k : keys()) {
    if (name != k.name) continue;
    if (eq == std::string::npos) {
      error = "setting '" + name + "' needs a value (" + name + "=N)";
      return false;
    }
    std::string value = assignment.substr(eq + 1);
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(value.c_str(), &end, 10);
    if (value.empty() || value[0] == '-' || *end != '\0' || errno != 0) {
      error = "setting '" + name + "' must be a whole number, not '" + value + "'";
      return false;
    }
    k.set(settings, v);
    return true;
  }
  error = "unknown setting '" + name + "'; known:";
  for (const Key& k : keys()) error += std::string(" ") + k.name;
  return false;
}

std::vector<std::string> settingKeys() {
  std::vector<std::string> out;
  for (const Key& k : keys()) out.push_back(std::string(k.name) + "  (" + k.meaning + ")");
  return out;
}

}  // namespace tools
