#include "settings_keys.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace tools {

bool applySetting(gi::Settings& settings, const std::string& assignment, std::string& error) {
  size_t eq = assignment.find('=');
  std::string name = assignment.substr(0, eq);
  const gi::SettingInfo* k = gi::findSetting(name);
  if (!k) {
    error = "unknown setting '" + name + "'; known:";
    for (const gi::SettingInfo& s : gi::settingCatalogue()) error += std::string(" ") + s.key;
    return false;
  }
  if (eq == std::string::npos) {
    error = "setting '" + name + "' needs a value (" + name + "=N)";
    return false;
  }
  std::string value = assignment.substr(eq + 1);
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(value.c_str(), &end);
  const bool integer = k->kind != gi::SettingKind::Float;
  const bool whole = v >= 0.0 && v <= 1.8e19 && std::floor(v) == v;
  if (value.empty() || *end != '\0' || errno != 0 || !std::isfinite(v) || (integer && !whole)) {
    error =
        "setting '" + name + "' must be " + (integer ? "a whole number" : "a finite number") + ", not '" + value + "'";
    return false;
  }
  // Before the field holds it: a bool keeps 2 as true, a 32-bit field wraps past its range, and neither could
  // be told from a value in range afterwards (gi::validate's check and message).
  if (!gi::inRange(*k, v)) {
    error = gi::outOfRangeText(*k, v);
    return false;
  }
  k->set(settings, v);
  return true;
}

std::vector<std::string> settingKeys() {
  std::vector<std::string> out;
  for (const gi::SettingInfo& k : gi::settingCatalogue()) {
    out.push_back(std::string(k.key) + "  (" + k.meaning + (*k.unit ? std::string("; ") + k.unit : "") + "; " +
                  gi::rangeText(k) + ")");
  }
  return out;
}

std::vector<std::string> debugViewLines() {
  std::vector<std::string> out;
  for (const gi::DebugViewInfo& v : gi::debugViewCatalogue())
    out.push_back(std::to_string(uint32_t(v.view)) + "  " + v.name + ": " + v.meaning);
  return out;
}

std::vector<const char*> methodNames() {
  std::vector<const char*> names;
  for (const gi::MethodInfo& m : gi::methodCatalogue()) names.push_back(m.name);
  return names;
}

std::string methodList() {
  std::string list;
  for (const char* name : methodNames()) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

}  // namespace tools
