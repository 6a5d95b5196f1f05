// Module settings by name, for the command line: `--set raw.spp=4`.
// One table maps each key to its field, so gi-render, gi-bench and the demo
// agree on names; the module validates the values.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "gi/gi.h"

namespace tools {

// One setting: its command-line name, meaning with units, and a range for
// sliders (the module's validate() holds the real limits).
struct SettingKey {
  const char* name;      // "bounces", or "<method>.<knob>" ("aaf." keys serve aaf and aaf_ao)
  const char* meaning;
  bool integer;          // whole numbers only
  double sliderMin, sliderMax;
  std::function<void(gi::Settings&, double)> set;
  std::function<double(const gi::Settings&)> get;
};
const std::vector<SettingKey>& settingTable();
// The method whose name prefixes a method's keys: aaf_ao uses "aaf.", nhpsf and anhpsf use "hpsf.".
gi::Method keyOwner(gi::Method method);

// Applies "key=value"; false with a sentence in `error` for an unknown key or a malformed value.
bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error);
std::vector<std::string> settingKeys();

// Every method's name, in gi::Method's order, and the same joined by ", "
// (for help texts: the list is gi::methodName's, never written out again).
std::vector<const char*> methodNames();
std::string methodList();

}  // namespace tools
