// An engine that is not ours, embedding the installed GI package: Vulkan
// through the system loader with prototypes, its own instance and device
// (features from gi/device.h), two frames in flight with a fence each, and
// settings and size changed while frames are in flight. The scene is empty
// (every ray misses) and the G-buffer a camera-facing emissive plane cleared
// each frame, so the known answer is exact: the composite is the emission.
// Exit status 0 only if every check holds and validation (GI_VALIDATION=1)
// reported nothing.
//
//   standalone_host            run, print a summary
#include "vulkan_host.h"  // the host's own Vulkan (vulkan.h with prototypes), before gi.h

#include <gi/device.h>
#include <gi/gi.h>
#include <gi/scene.h>
#include <shared/gbuffer.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <glm/gtc/packing.hpp>  // unpackHalf1x16: the outputs are half floats

namespace {

int failures = 0;

void expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    failures++;
  }
}

// An empty scene (no meshes, no lights, black sky), built by the module:
// every ray misses. The upload is recorded into a command buffer of ours.
gi::Scene* createEmptyScene(const example::Host& h) {
  gi::SceneCreateDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;
  desc.instance = h.instance;
  desc.physicalDevice = h.physical;
  desc.device = h.device;
  desc.traversal = gi::Traversal::Compute;
  gi::Scene* scene = nullptr;
  gi::Error e;
  example::submitOnce(h, [&](VkCommandBuffer cmd) { e = gi::createScene(desc, gi::SceneContents{}, cmd, scene); });
  if (e) {
    std::fprintf(stderr, "gi::createScene: %s\n", e.message.c_str());
    std::exit(1);
  }
  gi::finishSceneUpload(scene);
  return scene;
}

// A pinhole at the origin looking down −Z (reversed-Z projection, y down).
// At the origin looking down −Z, 1 rad vertical field of view, reversed Z
// with an infinite far plane: plain column-major arrays, [column * 4 + row].
gi::CameraDesc camera(uint32_t width, uint32_t height) {
  gi::CameraDesc c{};
  for (int i = 0; i < 4; ++i) c.viewFromWorld[i * 5] = 1.0f;
  const float tanHalfFovY = std::tan(0.5f), aspect = float(width) / float(height);
  c.clipFromView[0] = 1.0f / (aspect * tanHalfFovY);
  c.clipFromView[5] = -1.0f / tanHalfFovY;  // y down
  c.clipFromView[11] = -1.0f;               // clip w = −z_view
  c.clipFromView[14] = 0.1f;                // near plane 0.1 m at depth 1
  return c;
}

constexpr float kEmission[3] = {1.0f, 2.0f, 3.0f};
constexpr float kPreExposure = 0.25f;  // the outputs hold light × this (half floats by default)

}  // namespace

int main() {
  if (gi::version() != (GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR)) {
    std::fprintf(stderr, "gi.h and the gi library linked differ in version\n");
    return 1;
  }
  example::Host h;
  example::createHost(std::getenv("GI_VALIDATION") != nullptr, h);
  gi::Scene* scene = createEmptyScene(h);
  constexpr uint32_t kMaxW = 64, kMaxH = 64, kFramesInFlight = 2, kFrames = 16;
  const VkFormat formats[gpu::GBUFFER_COLOR_COUNT] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM,
                                                      VK_FORMAT_R8G8_UNORM,          VK_FORMAT_R32G32B32A32_SFLOAT,
                                                      VK_FORMAT_R16G16_SFLOAT,       VK_FORMAT_R32_SFLOAT};
  // The G-buffer: what a plane one metre wide per metre of depth, 2 m away and facing the camera, writes.
  const VkClearColorValue clears[gpu::GBUFFER_COLOR_COUNT] = {
      {.float32 = {0, 0, 1, 1}}, {.float32 = {0.5f, 0.5f, 0.5f, 0}},
      {.float32 = {1, 0, 0, 0}}, {.float32 = {kEmission[0], kEmission[1], kEmission[2], 0}},
      {.float32 = {0, 0, 0, 0}}, {.float32 = {2, 0, 0, 0}}};
  example::Image gbuffer[gpu::GBUFFER_COLOR_COUNT];
  for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i)
    gbuffer[i] =
        example::createImage(h, formats[i], {kMaxW, kMaxH},
                             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
  const gi::GBufferViews views{
      gbuffer[gpu::GBUFFER_NORMAL].view,   gbuffer[gpu::GBUFFER_ALBEDO].view,
      gbuffer[gpu::GBUFFER_MATERIAL].view, gbuffer[gpu::GBUFFER_EMISSION].view,
      gbuffer[gpu::GBUFFER_MOTION].view,   gbuffer[gpu::GBUFFER_VIEWZ].view};  // depth: linear view Z

  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;  // the loader's: the module loads its own table through it
  desc.instance = h.instance;
  desc.physicalDevice = h.physical;
  desc.device = h.device;
  desc.width = kMaxW;
  desc.height = kMaxH;
  desc.maxWidth = kMaxW;
  desc.maxHeight = kMaxH;
  desc.framesInFlight = kFramesInFlight;
  desc.scene = gi::sceneDesc(scene);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  gi::Module* module = nullptr;

  // Out of memory is an error, not an abort: a budget below what hpsf needs
  // (its three 64×64 rgba32f outputs alone are 192 KiB).
  desc.memoryBudgetBytes = 128 << 10;
  gi::Error oom = gi::create(desc, settings, module);
  expect(oom.code == gi::ErrorCode::VulkanCall && oom.result == VK_ERROR_OUT_OF_DEVICE_MEMORY && !module,
         "create under a 128 KiB budget fails with VK_ERROR_OUT_OF_DEVICE_MEMORY");
  std::printf("under a 128 KiB budget: %s\n", oom.message.c_str());
  gi::destroy(module);  // null unless the check above failed
  module = nullptr;
  desc.memoryBudgetBytes = 0;
  if (gi::Error e = gi::create(desc, settings, module)) {
    std::fprintf(stderr, "gi::create: %s\n", e.message.c_str());
    return 1;
  }

  VkCommandBuffer cmds[kFramesInFlight];
  VkCommandBufferAllocateInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmdInfo.commandPool = h.pool;
  cmdInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cmdInfo.commandBufferCount = kFramesInFlight;
  EXAMPLE_CHECK(vkAllocateCommandBuffers(h.device, &cmdInfo, cmds));
  VkFence fences[kFramesInFlight];
  for (VkFence& f : fences) {
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    EXAMPLE_CHECK(vkCreateFence(h.device, &fenceInfo, nullptr, &f));
  }

  uint32_t width = kMaxW, height = kMaxH;
  uint64_t rays = 0;
  for (uint32_t frame = 0; frame < kFrames; ++frame) {
    const uint32_t slot = frame % kFramesInFlight;
    EXAMPLE_CHECK(vkWaitForFences(h.device, 1, &fences[slot], VK_TRUE, UINT64_MAX));
    if (frame >= kFramesInFlight) {
      gi::FrameStats st;
      expect(gi::frameStats(module, frame - kFramesInFlight, st) && st.frameIndex == frame - kFramesInFlight,
             "the stats of the frame whose fence signalled are ready");
      rays += st.raysTraced;
    }
    // Changes while the previous frame is still in flight: no idle GPU needed.
    if (frame == 6) {
      settings.method = gi::Method::Gif;
      if (gi::Error e = gi::setSettings(module, settings)) std::fprintf(stderr, "%s\n", e.message.c_str()), failures++;
    }
    if (frame == 10) {
      width = 48;
      height = 40;
      if (gi::Error e = gi::resize(module, width, height)) std::fprintf(stderr, "%s\n", e.message.c_str()), failures++;
    }
    EXAMPLE_CHECK(vkResetFences(h.device, 1, &fences[slot]));
    VkCommandBuffer cmd = cmds[slot];
    EXAMPLE_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    EXAMPLE_CHECK(vkBeginCommandBuffer(cmd, &begin));
    // "Raster" the G-buffer: clear it (after the last frame's GI passes read it).
    VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i) {
      VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
      b.srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
      b.dstStageMask = VK_PIPELINE_STAGE_2_CLEAR_BIT;
      b.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
      b.oldLayout = frame == 0 ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_GENERAL;
      b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
      b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      b.image = gbuffer[i].image;
      b.subresourceRange = all;
      VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
      dep.imageMemoryBarrierCount = 1;
      dep.pImageMemoryBarriers = &b;
      vkCmdPipelineBarrier2(cmd, &dep);
      vkCmdClearColorImage(cmd, gbuffer[i].image, VK_IMAGE_LAYOUT_GENERAL, &clears[i], 1, &all);
    }
    example::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    const gi::CameraDesc cam = camera(width, height);
    gi::FrameInputs inputs{views, cam, cam, frame};
    inputs.preExposure = kPreExposure;
    if (gi::Error e = gi::recordFrame(module, cmd, inputs)) {
      std::fprintf(stderr, "%s\n", e.message.c_str());
      return 1;
    }
    EXAMPLE_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    EXAMPLE_CHECK(vkQueueSubmit(h.queue, 1, &submit, fences[slot]));
  }
  EXAMPLE_CHECK(vkDeviceWaitIdle(h.device));
  gi::FrameStats last;
  expect(gi::frameStats(module, kFrames - 1, last), "the last frame's stats once the device is idle");
  rays += last.raysTraced;
  expect(rays > 0, "the plane's pixels traced paths");

  // The known answer: every ray misses and there are no lights, so the composite is the emission.
  expect(gi::outputs(module).format == VK_FORMAT_R16G16B16A16_SFLOAT, "half-float outputs by default");
  example::Buffer readback =
      example::createBuffer(h, VkDeviceSize(width) * height * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  example::submitOnce(h, [&](VkCommandBuffer cmd) {
    example::recordReadback(cmd, gi::outputs(module).composite, {width, height}, readback);
  });
  const uint16_t* texels = static_cast<const uint16_t*>(readback.mapped);
  double worst = 0.0;  // relative
  for (size_t p = 0; p < size_t(width) * height; ++p)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, double(std::fabs(glm::unpackHalf1x16(texels[4 * p + c]) / kPreExposure - kEmission[c]) /
                                     kEmission[c]));
  expect(worst < 1e-3, "the composite equals the emission (to half-float rounding, pre-exposure divided out)");
  std::printf(
      "%u frames, %u in flight, hpsf then gif, %ux%u then %ux%u: %llu rays, composite within %.2g (relative) of the "
      "emission, %.1f MiB in %u device allocations, %u validation messages\n",
      kFrames, kFramesInFlight, kMaxW, kMaxH, width, height, (unsigned long long)rays, worst,
      double(last.memoryBytes) / 1048576.0, last.deviceAllocations, h.validationMessages);

  example::destroyBuffer(h, readback);
  gi::destroy(module);
  for (VkFence f : fences) vkDestroyFence(h.device, f, nullptr);
  for (example::Image& img : gbuffer) example::destroyImage(h, img);
  gi::destroyScene(scene);
  const uint32_t validationMessages = h.validationMessages;
  example::destroyHost(h);
  if (validationMessages > 0) std::fprintf(stderr, "FAILED: %u validation messages\n", validationMessages);
  return failures == 0 && validationMessages == 0 ? 0 : 1;
}
