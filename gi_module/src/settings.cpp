// Settings validation: every impossible value gets a named error that says
// which field, what value and what range.
#include <cstdio>

#include "gi/gi.h"

namespace gi {
namespace {

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
  }
  return "unknown";
}

bool methodFromName(const std::string& name, Method& out) {
  for (Method m : {Method::Raw})
    if (name == methodName(m)) {
      out = m;
      return true;
    }
  return false;
}

Error validate(const Settings& s) {
  if (uint32_t(s.method) > uint32_t(Method::Raw)) return {ErrorCode::UnknownMethod, "settings.method is not a known method"};
  if (s.maxBounces < 1 || s.maxBounces > 32) return outOfRange("settings.maxBounces", s.maxBounces, 1, 32);
  if (s.russianRouletteStart < 1 || s.russianRouletteStart > 64)
    return outOfRange("settings.russianRouletteStart", s.russianRouletteStart, 1, 64);
  if (uint32_t(s.debugView) > uint32_t(DebugView::Normal))
    return outOfRange("settings.debugView", uint32_t(s.debugView), 0, uint32_t(DebugView::Normal));
  if (s.raw.samplesPerPixel < 1 || s.raw.samplesPerPixel > 64)
    return outOfRange("settings.raw.samplesPerPixel", s.raw.samplesPerPixel, 1, 64);
  if (s.raw.maxAccumulatedFrames < 1 || s.raw.maxAccumulatedFrames > (1u << 20))
    return outOfRange("settings.raw.maxAccumulatedFrames", s.raw.maxAccumulatedFrames, 1, 1u << 20);
  return {};
}

}  // namespace gi
