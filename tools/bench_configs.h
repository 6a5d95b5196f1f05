// gi-bench's configurations: methods × swept settings × spp values, each with
// a readable label ("raw spp=4 bounces=2").
#pragma once
#include <string>
#include <vector>

#include "gi/gi.h"

namespace tools {

struct BenchConfig {
  std::string label;         // unique, file-name safe after sanitising
  std::string settingsText;  // the swept assignments, "bounces=2 raw.accumulate=0"
  uint32_t spp = 1;
  gi::Settings settings;
};

// `sweeps` is the value of --set: "raw.accumulate=0,1,bounces=1,2" (a token
// without '=' adds a value to the previous key). Keys prefixed by a method
// name apply only to that method; sweeping "<method>.spp" replaces `spps`
// for that method. Returns false with a sentence in `error`.
bool expandConfigs(const std::vector<std::string>& methods, const std::vector<uint32_t>& spps,
                   const std::string& sweeps, const gi::Settings& base, std::vector<BenchConfig>& out,
                   std::string& error);

// Sets the knob that --spp controls for the settings' method.
void setSamplesPerPixel(gi::Settings& settings, uint32_t spp);
// The active method's paths per pixel per frame (1 for AAF, which adapts).
uint32_t samplesPerPixel(const gi::Settings& settings);

}  // namespace tools
