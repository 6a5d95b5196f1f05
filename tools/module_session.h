// Headless frames through the GI module exactly as a game drives it: raster
// the G-buffer, gi::recordFrame, submit, wait, read the module's stats.
// Shared by gi-render and gi-bench.
#pragma once
#include <string>
#include <vector>

#include "gbuffer.h"
#include "gi/gi.h"
#include "image_io.h"
#include "path_tracer.h"

namespace tools {

struct ModuleSession {
  engine::GBuffer gbuffer;
  engine::GBufferPass gbufferPass;
  // The G-buffer pass's timestamps, one timer per frame in flight (frame
  // index mod framesInFlight, the module's); the module times its own passes.
  engine::GpuTimer timers[4];
  uint32_t framesInFlight = 2;
  gi::Module* module = nullptr;
  VkExtent2D extent{};
  // FrameInputs::preExposure: 1 / the scene's typical radiance, so lit
  // surfaces sit near 1 in the half-float outputs whatever the light's scale;
  // readModuleImages divides it out again.
  float preExposure = 1.0f;
  // The session's first failure (the engine's error style, engine/vk.h, kept with the session because
  // every frame call would otherwise take it): once set, the frame, warm-up and read-back calls below
  // do nothing and return empty results. Tools check it after their frames; tests' ScopedSession fails
  // the test when its session ends with one.
  std::string error;
};

struct FrameTiming {
  std::vector<gi::PassTiming> passes;  // gbuffer first, then the module's passes
  double totalMs = 0.0;
  uint64_t rays = 0;
};

// The engine's G-buffer as the module takes it.
gi::GBufferViews gbufferViews(const engine::GBuffer& gbuffer);
// What the module needs to know about a loaded scene.
gi::SceneDesc sceneDesc(const engine::SceneGpu& scene);
// The module's desc for this context, scene and size (defaults elsewhere).
gi::ModuleDesc moduleDesc(const engine::Context& ctx, const engine::SceneGpu& scene, VkExtent2D extent);
// `desc`: the module's desc when not moduleDesc()'s (a budget, callbacks, a maximum size).
bool createModuleSession(const engine::Context& ctx, const engine::SceneGpu& scene, VkExtent2D extent,
                         const gi::Settings& settings, ModuleSession& session, std::string& error,
                         const gi::ModuleDesc* desc = nullptr);
void destroyModuleSession(const engine::Context& ctx, ModuleSession& session);
// A new render size: waits for the device, makes a G-buffer of that size and resizes the module.
bool resizeModuleSession(const engine::Context& ctx, ModuleSession& session, VkExtent2D extent, std::string& error);

// The first dispatch of each program `settings` run, one submission each
// (gi::recordProgramWarmup), and one G-buffer raster from `camera` ("gbuffer",
// its pipelines' first draw): where the driver compiles at first use, each
// one's compile. After it, timed frames time no compiler.
struct ProgramWarmup {
  std::string name;
  double ms = 0.0;  // wall time of its warm-up submission
};
std::vector<ProgramWarmup> warmModulePrograms(const engine::Context& ctx, ModuleSession& session,
                                              const gi::Settings& settings, const engine::Scene& scene,
                                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera);

// Records one frame (G-buffer raster, then the module) into `cmd`; submits
// nothing. The frame recorded framesInFlight before it must have completed.

void recordModuleFrame(const engine::Context& ctx, VkCommandBuffer cmd, ModuleSession& session,
                       const engine::Scene& scene, const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                       const gpu::GpuCamera& previousCamera, uint32_t frameIndex);

// The G-buffer timer of frame `frameIndex` (read once that frame has completed).
inline const engine::GpuTimer& gbufferTimer(const ModuleSession& s, uint32_t frameIndex) {
  return s.timers[frameIndex % s.framesInFlight];
}

// Records and runs one frame; waits for it and returns its GPU timings.
FrameTiming renderModuleFrame(const engine::Context& ctx, ModuleSession& session, const engine::Scene& scene,
                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                              const gpu::GpuCamera& previousCamera, uint32_t frameIndex);

// The module's outputs and the G-buffer's albedo/normal/depth, as float images
// shaped like the reference's AOVs.
engine::ReferenceImages readModuleImages(const engine::Context& ctx, ModuleSession& session);

}  // namespace tools
