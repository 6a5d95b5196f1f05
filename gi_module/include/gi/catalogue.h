// The module's catalogues, each defined once (gi_module/src/catalogue.cpp):
// every setting with its key, field, range, unit and meaning; the methods;
// the debug views; the passes. gi::validate checks the settings against this
// table, the tools' --set and the demo's sliders are built from it, and help
// texts list methods, views and passes from it, so none of them can drift.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "gi/settings.h"

namespace gi {

enum class SettingKind : uint32_t {
  Uint,    // a whole number in [min, max]
  Float,   // a finite number in [min, max] ((min, max] when openMin)
  Bool,    // 0 or 1
  Choice,  // an enum's value in [min, max] (meaning lists them)
};

struct SettingInfo {
  const char* key;      // command-line and overlay name: "bounces", or "<method>.<knob>" ("aaf." serves aaf and
                        // aaf_ao, "hpsf." the three hash methods)
  const char* field;    // the member, as errors name it: "settings.hpsf.filterWidth"
  const char* unit;     // "pixels", "frames", ... ("" for pure numbers)
  const char* meaning;  // one line, without the unit
  SettingKind kind;
  double min, max;   // the valid range: validate() refuses anything else (NaN included)
  bool openMin;      // min itself is not valid
  uint32_t methods;  // bit (1 << Method) per method that reads it; 0 = every method
  double (*get)(const Settings&);
  void (*set)(Settings&, double);  // stores the value as the field's type (no range check: validate does)
  // A change makes the accumulated light wrong (its expectation changes, or it turns on a history that was
  // not kept while off): setSettings restarts the histories. Any other change keeps them (the ray budget,
  // sample counts, filter widths, the debug view, ...).
  bool restartsHistory = false;
  bool usedBy(Method m) const { return methods == 0 || (methods >> uint32_t(m)) & 1u; }
};
std::span<const SettingInfo> settingCatalogue();
const SettingInfo* findSetting(std::string_view key);  // null for an unknown key
// The valid range as errors, help texts and tooltips print it: "[1, 64]", "(0, 10000]".
std::string rangeText(const SettingInfo& setting);
// Whether `value` lies in the setting's range (NaN never does), and the error that says it does not:
// "settings.raw.samplesPerPixel = 0 is outside [1, 64]" (floats: %g).
bool inRange(const SettingInfo& setting, double value);
std::string outOfRangeText(const SettingInfo& setting, double value);

struct MethodInfo {
  Method method;
  const char* name;     // "hpsf": command lines, CSVs, the overlay
  const char* summary;  // one line: what it does and after whom
};
std::span<const MethodInfo> methodCatalogue();  // in gi::Method's order

struct DebugViewInfo {
  DebugView view;
  const char* name;     // short label: "hash occupancy"
  const char* meaning;  // what the image shows
  bool radiance;        // the composite holds light (× pre-exposure); otherwise a [0,1] picture, unscaled
};
std::span<const DebugViewInfo> debugViewCatalogue();  // in gi::DebugView's order

// Every pass the frame can record. FrameStats::passes name them; the frame
// script records them by this enum.
enum class Pass : uint32_t {
  ReservoirTemporal,
  ReservoirSpatial,
  ReservoirPick,
  RawTrace,
  AafSample,
  AafAdaptive,
  HpsfInsert,
  NhpsfPaths,
  AnhpsfPaths,
  HpsfClaim,
  HpsfValidate,
  HpsfResolve,
  HpsfLookup,
  TemporalGradient,
  TemporalSpread,
  Temporal,
  SvgfVariance,
  SvgfAtrous,
  Guidance,
  Sspsf,
  Bilateral,
  Atrous,
  GifMoments,
  GifBoxRows,
  GifBoxColumns,
  GifCoefficients,
  GifOutput,
  AafFilterDiffuseRows,
  AafFilterDiffuseColumns,
  AafFilterGlossyRows,
  AafFilterGlossyColumns,
  AafFilterGlossyEdgeRows,
  AafFilterGlossyEdgeColumns,
  Composite,
  GifSupersample,
  Count
};
struct PassInfo {
  Pass pass;
  const char* name;  // "hpsf_insert"
  bool tracesRays;   // a path-tracing pass: its time is what Mrays/s divide by
};
std::span<const PassInfo> passCatalogue();  // in Pass's order
inline const PassInfo& passInfo(Pass p) { return passCatalogue()[uint32_t(p)]; }
bool passTracesRays(std::string_view name);  // false for names not in the catalogue

}  // namespace gi
