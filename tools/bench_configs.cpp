#include "bench_configs.h"

#include <algorithm>

#include "cli.h"
#include "settings_keys.h"

namespace tools {

void setSamplesPerPixel(gi::Settings& settings, uint32_t spp) { gi::setTracedSamplesPerPixel(settings, spp); }

uint32_t samplesPerPixel(const gi::Settings& settings) { return std::max(1u, gi::tracedSamplesPerPixel(settings)); }

bool expandConfigs(const std::vector<std::string>& methods, const std::vector<uint32_t>& spps,
                   const std::string& sweeps, const gi::Settings& base, std::vector<BenchConfig>& out,
                   std::string& error) {
  // Parse "k=v1,v2,k2=v3" into (key, values).
  std::vector<std::pair<std::string, std::vector<std::string>>> keys;
  if (!sweeps.empty())
    for (const std::string& token : cli::splitList(sweeps)) {
      size_t eq = token.find('=');
      if (eq != std::string::npos)
        keys.push_back({token.substr(0, eq), {token.substr(eq + 1)}});
      else if (!keys.empty() && !token.empty())
        keys.back().second.push_back(token);
      else {
        error = "--set: '" + token + "' is not KEY=VALUE";
        return false;
      }
    }
  for (const std::string& methodName : methods) {
    gi::Method method;
    if (!gi::methodFromName(methodName, method)) {
      error = "unknown method '" + methodName + "'";
      return false;
    }
    // Keys this method reads (the catalogue says which); an unknown key is an error.
    std::vector<const std::pair<std::string, std::vector<std::string>>*> mine;
    for (const auto& k : keys) {
      const gi::SettingInfo* info = gi::findSetting(k.first);
      if (!info) {
        gi::Settings scratch;
        applySetting(scratch, k.first + "=0", error);  // the sentence that lists the known keys
        return false;
      }
      if (info->usedBy(method)) mine.push_back(&k);
    }
    // A swept "<method>.spp" replaces --spp for that method.
    bool sppSwept = false;
    for (const auto* k : mine) sppSwept |= k->first.ends_with(".spp");
    const std::vector<uint32_t> one = {0};
    // Cartesian product over the swept values (odometer order).
    std::vector<size_t> index(mine.size(), 0);
    while (true) {
      for (uint32_t spp : sppSwept || gi::isAaf(method) ? one : spps) {
        BenchConfig c;
        c.settings = base;
        c.settings.method = method;
        if (!sppSwept) setSamplesPerPixel(c.settings, spp);
        for (size_t i = 0; i < mine.size(); ++i) {
          std::string assignment = mine[i]->first + "=" + mine[i]->second[index[i]];
          if (!applySetting(c.settings, assignment, error)) return false;
          c.settingsText += (c.settingsText.empty() ? "" : " ") + assignment;
        }
        c.spp = gi::tracedSamplesPerPixel(c.settings);
        if (gi::Error e = gi::validate(c.settings)) {
          error = methodName + " " + c.settingsText + ": " + e.message;
          return false;
        }
        c.label = methodName + (sppSwept || c.spp == 0 ? "" : " spp=" + std::to_string(c.spp)) +
                  (c.settingsText.empty() ? "" : " " + c.settingsText);
        out.push_back(c);
      }
      size_t k = 0;
      while (k < mine.size() && ++index[k] == mine[k]->second.size()) index[k++] = 0;
      if (k == mine.size()) break;
    }
  }
  return true;
}

}  // namespace tools
