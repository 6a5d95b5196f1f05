#include "overlay.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

#include "settings_keys.h"

namespace demo {
namespace {

// A slider per tunable of the active method (the module's catalogue says
// which fields it reads), plus the method-independent ones; ranges are the
// ones validate() enforces, logarithmic where they span more than 100×.
bool tunables(gi::Settings& settings) {
  bool changed = false;
  for (const gi::SettingInfo& k : gi::settingCatalogue()) {
    if (!k.usedBy(settings.method)) continue;
    const std::string key = k.key;
    if (key == "view" || key == "ray_budget" || key == "seed") continue;  // own widgets
    // The knob's name and unit as the label (the method is chosen above); its meaning and range on hover.
    const size_t dot = key.find('.');
    std::string label =
        key.substr(dot == std::string::npos ? 0 : dot + 1) + (*k.unit ? std::string(", ") + k.unit : "") + "##" + key;
    const double value = k.get(settings);
    const bool logarithmic = k.max / std::max(k.min, 1.0) > 100.0;
    const ImGuiSliderFlags flags = logarithmic ? ImGuiSliderFlags_Logarithmic : 0;
    if (k.kind == gi::SettingKind::Bool) {
      bool on = value != 0.0;
      if (ImGui::Checkbox(label.c_str(), &on)) k.set(settings, on ? 1.0 : 0.0), changed = true;
    } else if (k.kind == gi::SettingKind::Float) {
      float v = float(value);
      if (ImGui::SliderFloat(label.c_str(), &v, float(k.min), float(k.max), "%.4g", flags))
        k.set(settings, double(v)), changed = true;
    } else {
      int v = int(value);
      if (ImGui::SliderInt(label.c_str(), &v, int(k.min), int(k.max), "%d", flags))
        k.set(settings, double(std::max(v, 0))), changed = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\n%s %s", k.meaning, k.field, gi::rangeText(k).c_str());
  }
  return changed;
}

// The last frame's passes as one stacked bar, each pass a colour, with its legend.
void passBar(const gi::FrameStats& stats, double gbufferMs) {
  std::vector<std::pair<std::string, double>> passes;
  if (gbufferMs > 0.0) passes.push_back({"gbuffer", gbufferMs});
  for (const gi::PassTiming& p : stats.passes) {
    auto it = std::find_if(passes.begin(), passes.end(), [&](const auto& q) { return q.first == p.name; });
    if (it != passes.end())
      it->second += p.ms;  // passes run several times a frame add up
    else
      passes.push_back({p.name, p.ms});
  }
  double total = 0.0;
  for (const auto& p : passes) total += p.second;
  if (total <= 0.0) return;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  ImVec2 origin = ImGui::GetCursorScreenPos();
  float width = ImGui::GetContentRegionAvail().x, height = 18.0f, x = origin.x;
  for (size_t i = 0; i < passes.size(); ++i) {
    float w = float(passes[i].second / total) * width;
    ImU32 colour = ImColor::HSV(float(i) / float(passes.size()), 0.65f, 0.9f);
    draw->AddRectFilled(ImVec2(x, origin.y), ImVec2(x + w, origin.y + height), colour);
    x += w;
  }
  ImGui::Dummy(ImVec2(width, height));
  for (size_t i = 0; i < passes.size(); ++i) {
    ImGui::ColorButton(passes[i].first.c_str(), ImColor::HSV(float(i) / float(passes.size()), 0.65f, 0.9f),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(10, 10));
    ImGui::SameLine();
    ImGui::Text("%-22s %8.2f ms", passes[i].first.c_str(), passes[i].second);
  }
}

}  // namespace

void recordFrameNumbers(OverlayState& state, const gi::FrameStats& stats, double gbufferMs, double cpuFrameMs) {
  state.totalMsHistory.push_back(float(stats.totalMs));
  while (state.totalMsHistory.size() > 120) state.totalMsHistory.pop_front();
  state.gbufferMs = gbufferMs;
  state.cpuFrameMs = cpuFrameMs;
}

bool buildOverlay(OverlayState& state, gi::Settings& settings, const gi::FrameStats& stats) {
  bool changed = false;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(440, ImGui::GetIO().DisplaySize.y - 16), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.8f);
  ImGui::Begin("GI module");
  ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.42f);

  // The combo lists gi::Method in its own order (tools::methodNames).
  int method = int(settings.method);
  std::vector<const char*> names = tools::methodNames();
  if (ImGui::Combo("method", &method, names.data(), int(names.size()))) {
    settings.method = gi::Method(uint32_t(method));
    changed = true;
  }
  int view = int(settings.debugView);
  std::vector<const char*> views;
  for (const gi::DebugViewInfo& v : gi::debugViewCatalogue()) views.push_back(v.name);
  if (ImGui::Combo("debug view", &view, views.data(), int(views.size()))) {
    settings.debugView = gi::DebugView(uint32_t(view));
    changed = true;
  }
  ImGui::SliderFloat("exposure", &state.exposure, 0.05f, 20.0f, "%.3g", ImGuiSliderFlags_Logarithmic);
  if (ImGui::CollapsingHeader("tunables", ImGuiTreeNodeFlags_DefaultOpen)) changed |= tunables(settings);
  if (!state.settingsError.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", state.settingsError.c_str());
  if (!state.compiling.empty())
    ImGui::TextColored(ImVec4(1, 0.85f, 0.3f, 1), "compiling %s... (the current method renders meanwhile)",
                       state.compiling.c_str());

  if (ImGui::CollapsingHeader("frame", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("module %.2f ms GPU   gbuffer %.2f ms   frame %.1f ms CPU", stats.totalMs, state.gbufferMs,
                state.cpuFrameMs);
    ImGui::Text("rays %.3g   spp %u   sanitized %u   memory %.1f MiB", double(stats.raysTraced), stats.samplesPerPixel,
                stats.sanitized, double(stats.memoryBytes) / 1048576.0);
    if (settings.reservoirs.sky)
      ImGui::Text("sky picks %u, %u saw the sky; its share and target x %.3f", stats.skyPicks.tested,
                  stats.skyPicks.visible, double(stats.skyPicks.visibility));
    std::vector<float> history(state.totalMsHistory.begin(), state.totalMsHistory.end());
    if (!history.empty())
      ImGui::PlotLines("module ms", history.data(), int(history.size()), 0, nullptr, 0.0f,
                       *std::max_element(history.begin(), history.end()) * 1.2f, ImVec2(0, 50));
    passBar(stats, state.gbufferMs);
  }
  if (gi::usesHashGrid(settings.method) && ImGui::CollapsingHeader("hash map", ImGuiTreeNodeFlags_DefaultOpen)) {
    const gi::FrameStats::Hash& h = stats.hash;
    ImGui::Text("occupancy %.1f%% (%u of %u cells), later cells %gx wider", 100.0 * h.occupancy(), h.occupied,
                h.capacity, h.secondaryWidth);
    ImGui::Text("inserts %u   failed %u   claimed %u   evicted %u", h.inserts, h.failedInserts, h.claimed, h.evicted);
    ImGui::Text("probe mean %.2f   max %u   overflows %u", double(h.meanProbe), h.maxProbe, h.overflows);
    ImGui::Text("stale histories cut %u", h.staleResets);
    if (settings.method == gi::Method::Anhpsf)
      ImGui::Text("continuation: mean depth %.2f, transported %.3g", double(h.meanContinuationDepth), h.transported);
  }
  if (ImGui::CollapsingHeader("budget", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (ImGui::Checkbox("budget mode: hold the module's GPU time", &state.budgetMode) && !state.budgetMode) {
      settings.rayBudget = 0;
      state.budget.rayBudget = 0;
      changed = true;
    }
    float target = float(state.budget.targetMs);
    if (ImGui::InputFloat("target ms", &target, 1.0f, 10.0f, "%.1f")) state.budget.targetMs = std::max(target, 0.1f);
    if (state.budgetMode)
      ImGui::Text("achieved %.2f ms (%+.0f%%): ray budget %.3g, %u spp", stats.totalMs,
                  100.0 * (stats.totalMs / state.budget.targetMs - 1.0), double(settings.rayBudget),
                  stats.samplesPerPixel);
  }
  if (ImGui::CollapsingHeader("scene", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("walkthrough (P)", &state.walkthrough);
    ImGui::Checkbox("move the light and an object", &state.animate);
    ImGui::Checkbox("tell the module when lights move (gi::invalidate)", &state.tellModuleLightsMoved);
    if (ImGui::Button("screenshot (F12)")) state.screenshotRequested = true;
    // Deforming meshes (gi::SceneInfo): the last measured level's cost against its cost as built, and the
    // rebuilds past SceneCreateDesc::rebuildCostRatio (shown once a mesh was measured).
    const gi::SceneInfo& info = state.scene;
    if (info.refitCostRatio > 0.0f || info.levelRebuilds > 0)
      ImGui::Text("deforming mesh BVH: cost %.2fx as built, %u rebuilds%s", double(info.refitCostRatio),
                  info.levelRebuilds, info.levelRebuildRunning ? " (one building)" : "");
    ImGui::TextDisabled("right mouse: look   WASD/QE: move   shift: faster");
  }
  ImGui::PopItemWidth();
  ImGui::End();
  return changed;
}

}  // namespace demo
