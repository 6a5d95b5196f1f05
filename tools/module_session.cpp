#include "module_session.h"

#include "camera.h"
#include "readback.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>

namespace tools {

gi::GBufferViews gbufferViews(const engine::GBuffer& g) {
  return {g.color[gpu::GBUFFER_NORMAL].view,   g.color[gpu::GBUFFER_ALBEDO].view, g.color[gpu::GBUFFER_MATERIAL].view,
          g.color[gpu::GBUFFER_EMISSION].view, g.color[gpu::GBUFFER_MOTION].view, g.color[gpu::GBUFFER_VIEWZ].view};
}

gi::SceneDesc sceneDesc(const engine::SceneGpu& scene) { return scene.desc; }

gi::ModuleDesc moduleDesc(const engine::Context& ctx, const engine::SceneGpu& scene, VkExtent2D extent) {
  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;  // volk's: the module loads its own table through it
  desc.instance = ctx.instance;
  desc.physicalDevice = ctx.physicalDevice;
  desc.device = ctx.device;
  desc.width = extent.width;
  desc.height = extent.height;
  desc.scene = sceneDesc(scene);
  desc.gbuffer = engine::moduleGBufferDesc();
  desc.debugLabels = ctx.debugUtils;
  return desc;
}

bool createModuleSession(const engine::Context& ctx, const engine::SceneGpu& scene, VkExtent2D extent,
                         const gi::Settings& settings, ModuleSession& s, std::string& error,
                         const gi::ModuleDesc* desc) {
  const gi::ModuleDesc created = desc ? *desc : moduleDesc(ctx, scene, extent);
  if (gi::Error e = gi::create(created, settings, s.module)) {
    error = e.message;
    return false;
  }
  s.framesInFlight = created.framesInFlight;
  s.extent = extent;
  s.preExposure = 1.0f / scene.desc.typicalRadiance;
  // At the largest render size (ModuleDesc::maxWidth × maxHeight): a smaller one renders into its top left.
  s.gbuffer = engine::createGBuffer(
      ctx, {std::max(extent.width, created.maxWidth), std::max(extent.height, created.maxHeight)}, error);
  s.gbuffer.renderExtent = extent;
  s.gbufferPass = engine::createGBufferPass(ctx, scene, error);
  for (uint32_t slot = 0; slot < s.framesInFlight; ++slot) s.timers[slot] = engine::createGpuTimer(ctx, error, 4);
  if (!error.empty()) destroyModuleSession(ctx, s);
  return error.empty();
}

void destroyModuleSession(const engine::Context& ctx, ModuleSession& s) {
  vkDeviceWaitIdle(ctx.device);
  gi::destroy(s.module);
  for (engine::GpuTimer& t : s.timers) engine::destroyGpuTimer(ctx, t);
  engine::destroyGBufferPass(ctx, s.gbufferPass);
  engine::destroyGBuffer(ctx, s.gbuffer);
  s = ModuleSession{};
}

std::vector<ProgramWarmup> warmModulePrograms(const engine::Context& ctx, ModuleSession& s,
                                              const gi::Settings& settings, const engine::Scene& scene,
                                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera) {
  std::vector<ProgramWarmup> out;
  const auto rasterStart = std::chrono::steady_clock::now();  // every frame rasters its G-buffer anew
  engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        engine::recordGBuffer(ctx, cmd, s.gbufferPass, scene, sceneGpu, s.gbuffer, camera, nullptr);
      },
      s.error);
  out.push_back(
      {"gbuffer", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - rasterStart).count()});
  for (const std::string& name : gi::programNames(s.module, settings)) {
    const auto start = std::chrono::steady_clock::now();
    gi::Error warmed;
    engine::submitAndWait(
        ctx, [&](VkCommandBuffer cmd) { warmed = gi::recordProgramWarmup(s.module, settings, cmd, name); }, s.error);
    if (warmed && s.error.empty()) s.error = "warming " + name + ": " + warmed.message;
    gi::finishProgramWarmup(s.module);
    out.push_back({name, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
  }
  if (!s.error.empty()) out.clear();
  return out;
}

bool resizeModuleSession(const engine::Context& ctx, ModuleSession& s, VkExtent2D extent, std::string& error) {
  if (gi::Error e = gi::resize(s.module, extent.width, extent.height)) {
    error = e.message;
    return false;
  }
  s.extent = extent;
  if (extent.width <= s.gbuffer.extent.width && extent.height <= s.gbuffer.extent.height) {
    s.gbuffer.renderExtent = extent;  // dynamic resolution: the same images, a smaller rectangle; no wait
    return true;
  }
  vkDeviceWaitIdle(ctx.device);
  engine::destroyGBuffer(ctx, s.gbuffer);
  s.gbuffer = engine::createGBuffer(ctx, extent, error);
  return error.empty();
}

void recordModuleFrame(const engine::Context& ctx, VkCommandBuffer cmd, ModuleSession& s, const engine::Scene& scene,
                       const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                       const gpu::GpuCamera& previousCamera, uint32_t frameIndex) {
  if (!s.error.empty()) return;
  engine::GpuTimer& timer = s.timers[frameIndex % s.framesInFlight];
  engine::resetGpuTimer(ctx, timer);
  gi::FrameInputs in;
  in.gbuffer = gbufferViews(s.gbuffer);
  in.camera = engine::moduleCamera(camera);
  in.previousCamera = engine::moduleCamera(previousCamera);
  in.frameIndex = frameIndex;
  in.preExposure = s.preExposure;
  // Frame script: raster the G-buffer, then the GI module's passes.
  engine::recordGBuffer(ctx, cmd, s.gbufferPass, scene, sceneGpu, s.gbuffer, camera, &timer);
  if (gi::Error e = gi::recordFrame(s.module, cmd, in)) {
    s.error = "frame " + std::to_string(frameIndex) + ": " + e.message;
    return;
  }
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

FrameTiming renderModuleFrame(const engine::Context& ctx, ModuleSession& s, const engine::Scene& scene,
                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                              const gpu::GpuCamera& previousCamera, uint32_t frameIndex) {
  FrameTiming t;
  engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) { recordModuleFrame(ctx, cmd, s, scene, sceneGpu, camera, previousCamera, frameIndex); },
      s.error);
  if (!s.error.empty()) return t;
  for (const engine::PassTime& p : engine::readPassTimes(ctx, gbufferTimer(s, frameIndex), s.error))
    t.passes.push_back({p.name, p.ms});
  gi::FrameStats st = gi::stats(s.module);
  t.passes.insert(t.passes.end(), st.passes.begin(), st.passes.end());
  for (const gi::PassTiming& p : t.passes) t.totalMs += p.ms;
  t.rays = st.raysTraced;
  return t;
}

engine::ReferenceImages readModuleImages(const engine::Context& ctx, ModuleSession& s) {
  engine::ReferenceImages out;
  if (!s.error.empty()) return out;
  gi::Outputs o = gi::outputs(s.module);
  const gi::OutputScales scale = gi::outputScales(gi::settings(s.module), s.preExposure);
  out.final = engine::readbackRgb(ctx, o.composite, o.compositeFormat, s.extent, s.error, scale.composite);
  out.direct = engine::readbackRgb(ctx, o.direct, o.format, s.extent, s.error, scale.direct);
  out.indirect = engine::readbackRgb(ctx, o.indirect, o.format, s.extent, s.error, scale.indirect);
  size_t n = size_t(s.extent.width) * s.extent.height;
  auto rendered = [&](uint32_t view) {  // the rectangle rendered into (the images may be larger)
    engine::Image image = s.gbuffer.color[view];
    image.extent = s.extent;
    return image;
  };
  const VkImageLayout general = VK_IMAGE_LAYOUT_GENERAL;
  std::vector<std::byte> albedo = engine::readbackImage(ctx, rendered(gpu::GBUFFER_ALBEDO), general, 4, s.error);
  std::vector<std::byte> normal = engine::readbackImage(ctx, rendered(gpu::GBUFFER_NORMAL), general, 8, s.error);
  std::vector<std::byte> depth = engine::readbackImage(ctx, rendered(gpu::GBUFFER_VIEWZ), general, 4, s.error);
  if (!s.error.empty()) return engine::ReferenceImages{};
  out.albedo = engine::FloatImage(s.extent.width, s.extent.height, 3);
  out.normal = engine::FloatImage(s.extent.width, s.extent.height, 3);
  out.depth = engine::FloatImage(s.extent.width, s.extent.height, 1);
  for (size_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) {
      out.albedo.pixels[3 * p + c] = float(uint8_t(albedo[4 * p + c])) / 255.0f;
      uint16_t h;
      std::memcpy(&h, &normal[8 * p + 2 * c], 2);
      out.normal.pixels[3 * p + c] = engine::halfToFloat(h);
    }
    std::memcpy(&out.depth.pixels[p], &depth[4 * p], 4);
  }
  return out;
}

}  // namespace tools
