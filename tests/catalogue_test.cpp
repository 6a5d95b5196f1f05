// The module's catalogues are the one source of settings, methods, debug
// views and passes: every default lies inside its range, validate() refuses
// each field just outside it and names the field, --set reaches every field,
// and the lists are complete and unique.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "gi/catalogue.h"
#include "gi/gi.h"
#include "settings_keys.h"

TEST(Catalogue, EveryDefaultIsInsideItsRangeAndValid) {
  const gi::Settings defaults;
  for (const gi::SettingInfo& k : gi::settingCatalogue()) {
    const double v = k.get(defaults);
    EXPECT_TRUE((k.openMin ? v > k.min : v >= k.min) && v <= k.max) << k.key << " = " << v;
  }
  for (uint32_t m = 0; m < gi::kMethodCount; ++m) {
    gi::Settings s;
    s.method = gi::Method(m);
    EXPECT_FALSE(gi::validate(s)) << gi::methodName(s.method) << ": " << gi::validate(s).message;
  }
}

TEST(Catalogue, ValidateRefusesEachFieldJustOutsideItsRangeAndNamesIt) {
  for (const gi::SettingInfo& k : gi::settingCatalogue()) {
    const bool whole = k.kind != gi::SettingKind::Float;
    const double above = whole ? k.max + 1 : k.max * 1.5 + 1;
    std::vector<double> outside = {above};
    if (k.openMin)
      outside.push_back(k.min);
    else if (k.min > 0)
      outside.push_back(whole ? k.min - 1 : k.min * 0.5);
    if (!whole) outside.push_back(std::nan(""));
    for (double v : outside) {
      if (k.kind == gi::SettingKind::Bool) continue;  // a bool holds 0 or 1 only
      if (k.key == std::string("seed") || k.key == std::string("hpsf.capacity") || k.key == std::string("ray_budget"))
        if (v > k.max)
          continue;  // seed's range is the whole uint32; capacity's and the budget's tops are exercised below
      gi::Settings s;
      k.set(s, v);
      gi::Error e = gi::validate(s);
      EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange) << k.key << " = " << v;
      EXPECT_NE(e.message.find(k.field), std::string::npos) << k.key << ": " << e.message;
    }
  }
  gi::Settings s;
  s.hpsf.capacity = 1u << 22;
  EXPECT_NE(gi::validate(s).message.find("settings.hpsf.capacity"), std::string::npos);
}

TEST(Catalogue, SetReachesEveryFieldThroughItsKey) {
  for (const gi::SettingInfo& k : gi::settingCatalogue()) {
    gi::Settings s;
    const double v = k.kind == gi::SettingKind::Float ? (k.min + k.max) * 0.5 : std::floor((k.min + k.max) * 0.5);
    std::string error;
    char text[64];
    std::snprintf(text, sizeof(text), "%.17g", v);
    ASSERT_TRUE(tools::applySetting(s, std::string(k.key) + "=" + text, error)) << error;
    EXPECT_NEAR(k.get(s), v, std::abs(v) * 1e-6 + (k.kind == gi::SettingKind::Bool ? 1.0 : 0.0)) << k.key;
  }
  std::string error;
  gi::Settings s;
  EXPECT_FALSE(tools::applySetting(s, "hpsf.nonsense=1", error));
  EXPECT_NE(error.find("hpsf.width"), std::string::npos) << "the error lists the known keys";
  // A value outside the range is refused before the field holds it: a bool would keep 2 as true.
  EXPECT_FALSE(tools::applySetting(s, "raw.accumulate=2", error));
  EXPECT_EQ(error, "settings.raw.temporalAccumulation = 2 is outside [0, 1]");
  EXPECT_FALSE(tools::applySetting(s, "hpsf.capacity=8589934592", error)) << "past 32 bits";
  EXPECT_FALSE(s.raw.temporalAccumulation) << "a refused value leaves the field as it was";
}

TEST(Catalogue, MethodsViewsAndPassesAreCompleteAndUnique) {
  std::set<std::string> names;
  for (const gi::MethodInfo& m : gi::methodCatalogue()) {
    gi::Method back;
    ASSERT_TRUE(gi::methodFromName(m.name, back));
    EXPECT_EQ(back, m.method);
    names.insert(m.name);
  }
  EXPECT_EQ(names.size(), size_t(gi::kMethodCount));
  ASSERT_EQ(gi::debugViewCatalogue().size(), size_t(gi::kDebugViewCount));
  for (uint32_t v = 0; v < gi::kDebugViewCount; ++v) EXPECT_EQ(gi::debugViewCatalogue()[v].view, gi::DebugView(v));
  std::set<std::string> passes;
  for (const gi::PassInfo& p : gi::passCatalogue()) passes.insert(p.name);
  EXPECT_EQ(passes.size(), size_t(gi::Pass::Count));
  for (const char* tracing :
       {"raw_trace", "aaf_sample", "aaf_adaptive", "hpsf_insert", "nhpsf_paths", "anhpsf_paths", "gif_supersample"})
    EXPECT_TRUE(gi::passTracesRays(tracing)) << tracing;
  EXPECT_FALSE(gi::passTracesRays("composite"));
  // Every method has settings of its own besides the global ones (aaf_ao shares aaf's).
  for (const gi::MethodInfo& m : gi::methodCatalogue()) {
    int own = 0;
    for (const gi::SettingInfo& k : gi::settingCatalogue()) own += k.methods != 0 && k.usedBy(m.method);
    EXPECT_GT(own, 0) << m.name;
  }
}
