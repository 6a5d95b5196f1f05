// The demo's Dear ImGui panel: method switch, every tunable of the method as
// a slider in its real units, the debug-view picker, per-pass GPU time (a
// stacked bar and a history plot), hash-map telemetry, deforming meshes' BVH measure, and budget mode.
#pragma once
#include <deque>
#include <string>

#include "gi/budget.h"
#include "gi/gi.h"
#include "gi/scene.h"

namespace demo {

struct OverlayState {
  // Set by the panel, read by the frame loop.
  bool walkthrough = true;             // scripted camera path (key P)
  bool animate = true;                 // the moving light and object
  bool tellModuleLightsMoved = false;  // gi::invalidate(LightsChanged) while the light moves
  bool budgetMode = false;
  bool screenshotRequested = false;
  float exposure = 1.0f;
  gi::BudgetController budget;
  std::string settingsError;  // the module's answer to the last rejected change
  std::string compiling;      // a method whose programs are being readied (the old one renders meanwhile)
  // Shown by the panel.
  std::deque<float> totalMsHistory;  // module GPU ms per frame, newest last
  double gbufferMs = 0.0;
  double cpuFrameMs = 0.0;
  gi::SceneInfo scene;  // the module scene's facts after this frame's updates (deforming meshes' measure)
};

// Builds the panel between ImGui::NewFrame and ImGui::Render. Returns true
// when `settings` changed (the caller applies them with gi::setSettings).
bool buildOverlay(OverlayState& state, gi::Settings& settings, const gi::FrameStats& stats);

// Remembers a frame's numbers for the plots.
void recordFrameNumbers(OverlayState& state, const gi::FrameStats& stats, double gbufferMs, double cpuFrameMs);

}  // namespace demo
