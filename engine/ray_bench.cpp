#include "ray_bench.h"

#include <cstring>

#include "compute_program.h"
#include "gpu_timer.h"
#include "ray_bench.comp.h"
#include "ray_bench.comp.compute.h"
#include "shared/ray_bench.h"

namespace engine {

RayBenchResult runRayBench(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera, uint32_t kind,
                           uint32_t traversal, std::string& error, uint32_t pathsPerPixel, uint32_t rounds) {
  if (!error.empty()) return {};
  uint32_t w = uint32_t(camera.imageSize.x), h = uint32_t(camera.imageSize.y);
  const Binding bindings[] = {{gpu::RB_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
                              {gpu::RB_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                              {gpu::RB_BINDING_COUNTER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
  DescriptorSet set = createDescriptorSet(ctx, bindings, error);
  Buffer cameraBuffer =
      createBuffer(ctx, sizeof(camera), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryKind::HostVisible, error);
  Buffer output =
      createBuffer(ctx, sizeof(float) * w * h, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::DeviceLocal, error);
  Buffer counter =
      createBuffer(ctx, sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::HostVisible, error);
  if (cameraBuffer.mapped) std::memcpy(cameraBuffer.mapped, &camera, sizeof(camera));
  DescriptorWriter(set.set)
      .buffer(gpu::RB_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, cameraBuffer.buffer)
      .buffer(gpu::RB_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, output.buffer)
      .buffer(gpu::RB_BINDING_COUNTER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, counter.buffer)
      .write(ctx.vk);
  VkDescriptorSetLayout layouts[] = {scene.set.layout, set.layout};
  ComputeProgram program =
      createComputeProgram(ctx, GI_SCENE_SPIRV(traversal, ray_bench_comp), layouts, sizeof(gpu::RayBenchPush),
                           {RB_GROUP_SIZE, RB_GROUP_SIZE}, error, scene.specialization());
  GpuTimer timer = createGpuTimer(ctx, error, 2);
  RayBenchResult result;
  VkDescriptorSet sets[] = {scene.set.set, set.set};
  for (uint32_t round = 0; round <= rounds && error.empty(); ++round) {
    std::memset(counter.mapped, 0, sizeof(uint32_t));
    resetGpuTimer(ctx, timer);
    submitAndWait(
        ctx,
        [&](VkCommandBuffer cmd) {
          beginPass(ctx, cmd, timer, "ray_bench");
          dispatch(ctx, cmd, program, sets, {w, h}, gpu::RayBenchPush{round, pathsPerPixel, kind, 0});
          memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
          endPass(ctx, cmd, timer);
        },
        error);
    if (round == 0 || !error.empty()) continue;  // warm-up: first dispatches may include shader compilation
    uint32_t rays;
    std::memcpy(&rays, counter.mapped, sizeof(rays));
    result.rays += rays;
    for (const PassTime& t : readPassTimes(ctx, timer, error)) result.gpuMs += t.ms;
  }
  if (!error.empty()) result = RayBenchResult{};
  destroyGpuTimer(ctx, timer);
  destroyComputeProgram(ctx, program);
  destroyBuffer(ctx, counter);
  destroyBuffer(ctx, output);
  destroyBuffer(ctx, cameraBuffer);
  destroyDescriptorSet(ctx, set);
  return result;
}

RayRates measureRayRates(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera, uint32_t traversal,
                         std::string& error, uint32_t pathsPerPixel, uint32_t rounds) {
  RayBenchResult primary =
      runRayBench(ctx, scene, camera, gpu::RB_KIND_PRIMARY, traversal, error, pathsPerPixel, rounds);
  auto extra = [&](uint32_t kind) {
    RayBenchResult r = runRayBench(ctx, scene, camera, kind, traversal, error, pathsPerPixel, rounds);
    double rays = double(r.rays) - double(primary.rays), ms = r.gpuMs - primary.gpuMs;
    return rays > 0.0 && ms > 0.0 ? rays / (ms * 1e3) : 0.0;
  };
  RayRates rates;
  rates.primary = primary.mraysPerSecond();
  rates.diffuse = extra(gpu::RB_KIND_DIFFUSE);
  rates.shadow = extra(gpu::RB_KIND_SHADOW);
  return error.empty() ? rates : RayRates{};
}

}  // namespace engine
