// Module settings by name, for the command line: `--set raw.spp=4`. The keys,
// their fields, ranges, units and meanings are the module's own catalogue
// (gi/catalogue.h), so gi-render, gi-bench and the demo agree with validate().
#pragma once
#include <string>
#include <vector>

#include "gi/catalogue.h"
#include "gi/gi.h"

namespace tools {

// Applies "key=value"; false with a sentence in `error` for an unknown key or a malformed value
// (the range is the module's to check: gi::validate names the field).
bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error);
// One help line per key: "hpsf.width  (filter width: ...; pixels; [0.5, 256])".
std::vector<std::string> settingKeys();
// One help line per debug view: "13  hash cells: HPSF: each pixel's cell, ...".
std::vector<std::string> debugViewLines();

// Every method's name, in gi::Method's order, and the same joined by ", ".
std::vector<const char*> methodNames();
std::string methodList();

}  // namespace tools
