// Module settings by name, for the command line: `--set raw.spp=4`.
// One table maps each key to its field, so gi-render, gi-bench and the demo
// agree on names; the module validates the values.
#pragma once
#include <string>
#include <vector>

#include "gi/gi.h"

namespace tools {

// Applies "key=value"; false with a sentence in `error` for an unknown key or a malformed value.
bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error);
std::vector<std::string> settingKeys();

}  // namespace tools
