#include "path_tracer.h"

#include <chrono>
#include <cstring>

#include "path_trace.comp.h"
#include "path_trace.comp.compute.h"

namespace engine {

PathTracer createPathTracer(const Context& ctx, const SceneGpu& scene, VkExtent2D extent, std::string& error) {
  PathTracer pt;
  if (!error.empty()) return pt;
  pt.extent = extent;
  const Binding bindings[] = {
      {gpu::PT_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      {gpu::PT_BINDING_FINAL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::PT_BINDING_DIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::PT_BINDING_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::PT_BINDING_ALBEDO_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::PT_BINDING_NORMAL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::PT_BINDING_RAY_COUNTER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
  };
  pt.set = createDescriptorSet(ctx, bindings, error);
  pt.camera =
      createBuffer(ctx, sizeof(gpu::GpuCamera), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryKind::HostVisible, error);
  pt.rayCounter =
      createBuffer(ctx, sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::HostVisible, error);
  for (Image& img : pt.accum)
    img = createImage(ctx, extent, VK_FORMAT_R32G32B32A32_SFLOAT,
                      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, error);
  makeStorageImagesGeneral(ctx, pt.accum, error);
  if (!error.empty()) {
    destroyPathTracer(ctx, pt);
    return pt;
  }
  std::memset(pt.rayCounter.mapped, 0, sizeof(uint32_t));
  DescriptorWriter w(pt.set.set);
  w.buffer(gpu::PT_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, pt.camera.buffer)
      .storageImage(gpu::PT_BINDING_FINAL, pt.accum[0].view)
      .storageImage(gpu::PT_BINDING_DIRECT, pt.accum[1].view)
      .storageImage(gpu::PT_BINDING_INDIRECT, pt.accum[2].view)
      .storageImage(gpu::PT_BINDING_ALBEDO_DEPTH, pt.accum[3].view)
      .storageImage(gpu::PT_BINDING_NORMAL, pt.accum[4].view)
      .buffer(gpu::PT_BINDING_RAY_COUNTER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, pt.rayCounter.buffer)
      .write(ctx.vk);
  VkDescriptorSetLayout layouts[] = {scene.set.layout, pt.set.layout};
  pt.program =
      createComputeProgram(ctx, GI_SCENE_SPIRV(ctx.traversalId(), path_trace_comp), layouts,
                           sizeof(gpu::PathTracerPush), {PT_GROUP_SIZE, PT_GROUP_SIZE}, error, scene.specialization());
  if (!error.empty()) destroyPathTracer(ctx, pt);
  return pt;
}

void destroyPathTracer(const Context& ctx, PathTracer& pt) {
  destroyComputeProgram(ctx, pt.program);
  destroyDescriptorSet(ctx, pt.set);
  destroyBuffer(ctx, pt.camera);
  destroyBuffer(ctx, pt.rayCounter);
  for (Image& img : pt.accum) destroyImage(ctx, img);
  pt = PathTracer{};
}

void recordPathTrace(const Context& ctx, VkCommandBuffer cmd, PathTracer& pt, const SceneGpu& scene,
                     const gpu::GpuCamera& camera, const ReferenceSettings& settings, uint32_t firstSample,
                     uint32_t samples, GpuTimer* timer) {
  std::memcpy(pt.camera.mapped, &camera, sizeof(camera));
  gpu::PathTracerPush push{};
  push.seed = settings.seed;
  push.firstSample = firstSample;
  push.samplesPerDispatch = samples;
  push.maxBounces = settings.maxBounces;
  push.pixelJitter = settings.pixelJitter ? 1u : 0u;
  push.russianRouletteStart = settings.russianRouletteStart;
  if (timer) beginPass(ctx, cmd, *timer, "path_trace");
  // Sums from the previous dispatch must land before this one reads them.
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  VkDescriptorSet sets[] = {scene.set.set, pt.set.set};
  dispatch(ctx, cmd, pt.program, sets, {pt.extent.width, pt.extent.height}, push);
  if (timer) endPass(ctx, cmd, *timer);
  pt.samples = firstSample + samples;
}

void warmPathTracer(const Context& ctx, VkCommandBuffer cmd, const PathTracer& pt, const SceneGpu& scene) {
  VkDescriptorSet sets[] = {scene.set.set, pt.set.set};
  warmUp(ctx, cmd, pt.program, sets);
}

uint64_t takeRayCount(PathTracer& pt) {
  uint32_t rays;
  std::memcpy(&rays, pt.rayCounter.mapped, sizeof(rays));
  std::memset(pt.rayCounter.mapped, 0, sizeof(rays));
  return rays;
}

ReferenceImages readReferenceImages(const Context& ctx, const PathTracer& pt, std::string& error) {
  uint32_t w = pt.extent.width, h = pt.extent.height;
  float inv = pt.samples > 0 ? 1.0f / float(pt.samples) : 0.0f;
  auto read = [&](int i) {
    std::vector<std::byte> raw = readbackImage(ctx, pt.accum[i], VK_IMAGE_LAYOUT_GENERAL, 16, error);
    std::vector<float> f(raw.size() / 4);
    std::memcpy(f.data(), raw.data(), raw.size());
    return f;
  };
  ReferenceImages out;
  FloatImage* rgb[] = {&out.final, &out.direct, &out.indirect, &out.albedo, &out.normal};
  const int source[] = {0, 1, 2, 3, 4};
  for (int k = 0; k < 5; ++k) {
    std::vector<float> f = read(source[k]);
    if (!error.empty()) return ReferenceImages{};
    *rgb[k] = FloatImage(w, h, 3);
    if (k == 3) out.depth = FloatImage(w, h, 1);
    for (size_t p = 0; p < size_t(w) * h; ++p) {
      for (int c = 0; c < 3; ++c) rgb[k]->pixels[3 * p + c] = f[4 * p + c] * inv;
      if (k == 3) out.depth.pixels[p] = f[4 * p + 3] * inv;
    }
  }
  return out;
}

ReferenceRun renderReference(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera,
                             const ReferenceSettings& settings, uint32_t spp, uint32_t samplesPerSubmit,
                             std::string& error) {
  ReferenceRun run;
  auto start = std::chrono::steady_clock::now();
  PathTracer pt = createPathTracer(ctx, scene, {uint32_t(camera.imageSize.x), uint32_t(camera.imageSize.y)}, error);
  GpuTimer timer = createGpuTimer(ctx, error, 4);
  if (error.empty()) takeRayCount(pt);
  const auto warmStart = std::chrono::steady_clock::now();
  submitAndWait(
      ctx, [&](VkCommandBuffer cmd) { warmPathTracer(ctx, cmd, pt, scene); }, error);
  run.firstDispatchMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - warmStart).count();
  for (uint32_t done = 0; done < spp && error.empty();) {
    uint32_t n = std::min(std::max(samplesPerSubmit, 1u), spp - done);
    resetGpuTimer(ctx, timer);
    submitAndWait(
        ctx, [&](VkCommandBuffer cmd) { recordPathTrace(ctx, cmd, pt, scene, camera, settings, done, n, &timer); },
        error);
    for (const PassTime& t : readPassTimes(ctx, timer, error)) run.gpuMs += t.ms;
    if (error.empty()) run.rays += takeRayCount(pt);
    done += n;
  }
  run.images = readReferenceImages(ctx, pt, error);
  destroyGpuTimer(ctx, timer);
  destroyPathTracer(ctx, pt);
  run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace engine
