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
      ctx, {std::max(extent.width, created.maxWidth), std::max(extent.height, created.maxHeight)});
  s.gbuffer.renderExtent = extent;
  s.gbufferPass = engine::createGBufferPass(ctx, scene);
  for (uint32_t slot = 0; slot < s.framesInFlight; ++slot) s.timers[slot] = engine::createGpuTimer(ctx, 4);
  return true;
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
  engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
    engine::recordGBuffer(ctx, cmd, s.gbufferPass, scene, sceneGpu, s.gbuffer, camera, nullptr);
  });
  out.push_back(
      {"gbuffer", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - rasterStart).count()});
  for (const std::string& name : gi::programNames(s.module, settings)) {
    const auto start = std::chrono::steady_clock::now();
    engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
      if (gi::Error e = gi::recordProgramWarmup(s.module, settings, cmd, name)) {
        std::fprintf(stderr, "warmModulePrograms: %s\n", e.message.c_str());  // a bug: the names are the module's
        std::abort();
      }
    });
    gi::finishProgramWarmup(s.module);
    out.push_back({name, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
  }
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
  s.gbuffer = engine::createGBuffer(ctx, extent);
  return true;
}

void recordModuleFrame(const engine::Context& ctx, VkCommandBuffer cmd, ModuleSession& s, const engine::Scene& scene,
                       const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                       const gpu::GpuCamera& previousCamera, uint32_t frameIndex) {
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
    std::fprintf(stderr, "%s\n", e.message.c_str());  // every view above is set: a bug in this file
    std::abort();
  }
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_HOST_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

FrameTiming renderModuleFrame(const engine::Context& ctx, ModuleSession& s, const engine::Scene& scene,
                              const engine::SceneGpu& sceneGpu, const gpu::GpuCamera& camera,
                              const gpu::GpuCamera& previousCamera, uint32_t frameIndex) {
  engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
    recordModuleFrame(ctx, cmd, s, scene, sceneGpu, camera, previousCamera, frameIndex);
  });
  FrameTiming t;
  for (const engine::PassTime& p : engine::readPassTimes(ctx, gbufferTimer(s, frameIndex)))
    t.passes.push_back({p.name, p.ms});
  gi::FrameStats st = gi::stats(s.module);
  t.passes.insert(t.passes.end(), st.passes.begin(), st.passes.end());
  for (const gi::PassTiming& p : t.passes) t.totalMs += p.ms;
  t.rays = st.raysTraced;
  return t;
}

engine::ReferenceImages readModuleImages(const engine::Context& ctx, const ModuleSession& s) {
  engine::ReferenceImages out;
  gi::Outputs o = gi::outputs(s.module);
  const gi::OutputScales scale = gi::outputScales(gi::settings(s.module), s.preExposure);
  out.final = engine::readbackRgb(ctx, o.composite, o.compositeFormat, s.extent, scale.composite);
  out.direct = engine::readbackRgb(ctx, o.direct, o.format, s.extent, scale.direct);
  out.indirect = engine::readbackRgb(ctx, o.indirect, o.format, s.extent, scale.indirect);
  size_t n = size_t(s.extent.width) * s.extent.height;
  auto rendered = [&](uint32_t view) {  // the rectangle rendered into (the images may be larger)
    engine::Image image = s.gbuffer.color[view];
    image.extent = s.extent;
    return image;
  };
  std::vector<std::byte> albedo = engine::readbackImage(ctx, rendered(gpu::GBUFFER_ALBEDO), VK_IMAGE_LAYOUT_GENERAL, 4);
  std::vector<std::byte> normal = engine::readbackImage(ctx, rendered(gpu::GBUFFER_NORMAL), VK_IMAGE_LAYOUT_GENERAL, 8);
  std::vector<std::byte> depth = engine::readbackImage(ctx, rendered(gpu::GBUFFER_VIEWZ), VK_IMAGE_LAYOUT_GENERAL, 4);
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
