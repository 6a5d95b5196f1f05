// Headless frames through the GI module exactly as a game drives it: raster
// the G-buffer, gi::recordFrame, submit, wait, read the module's stats.
// Shared by gi-render and gi-bench.
#pragma once
#include <string>

#include "gbuffer.h"
#include "gi/gi.h"
#include "image_io.h"
#include "path_tracer.h"

namespace tools {

struct ModuleSession {
  engine::GBuffer gbuffer;
  engine::GBufferPass gbufferPass;
  engine::GpuTimer timer;  // the G-buffer pass; the module times its own passes
  gi::Module* module = nullptr;
  VkExtent2D extent{};
};

struct FrameTiming {
  std::vector<gi::PassTiming> passes;  // gbuffer first, then the module's passes
  double totalMs = 0.0;
  uint64_t rays = 0;
};

// What the module needs to know about a loaded scene.
gi::SceneDesc sceneDesc(const engine::SceneGpu& scene);
bool createModuleSession(const engine::Context& ctx, const engine::SceneGpu& scene, VkExtent2D extent,
                         const gi::Settings& settings, ModuleSession& session, std::string& error);
void destroyModuleSession(const engine::Context& ctx, ModuleSession& session);
// A new render size: waits for the device, makes a G-buffer of that size and resizes the module.
bool resizeModuleSession(const engine::Context& ctx, ModuleSession& session, VkExtent2D extent, std::string& error);

// Records one frame (G-buffer raster, then the module) into `cmd`; submits nothing.
void recordModuleFrame(const engine::Context& ctx, VkCommandBuffer cmd, ModuleSession& session, const engine::Scene& scene,
                       const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera, const gpu::GpuCamera& previousCamera,
                       uint32_t frameIndex);

// Records and runs one frame; waits for it and returns its GPU timings.
FrameTiming renderModuleFrame(const engine::Context& ctx, ModuleSession& session, const engine::Scene& scene,
                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                              const gpu::GpuCamera& previousCamera, uint32_t frameIndex);

// The module's outputs and the G-buffer's albedo/normal/depth, as float images
// shaped like the reference's AOVs.
engine::ReferenceImages readModuleImages(const engine::Context& ctx, const ModuleSession& session);

}  // namespace tools
