// Issue 35 §1 (and issue 32 for skinned meshes): an engine with N frames in flight moves its scene every frame without serialising them.
// gi::updateInstances and gi::updateLights record the tables' writes into the frame's command buffer, so
// frame k+1's update cannot reach the tables frame k is still reading: 100 animated frames, 3 in flight,
// each waiting only on the fence of the frame 3 back, run clean under synchronization validation, make
// and allocate nothing after the first frames, and give bit for bit the images of the same frames run
// one at a time.
#include <gtest/gtest.h>

#include "animation.h"
#include "frame_slots.h"
#include "gpu_test.h"
#include "module_session.h"
#include "module_test_helpers.h"
#include "vulkan_call_counts.h"

namespace {

constexpr uint32_t kSize = 48, kFrames = 100, kInFlight = 3;

struct AnimatedRun {
  engine::ReferenceImages images;
  uint64_t moduleAllocationsAfterWarmup = 0, moduleAllocationsAtEnd = 0;
};

// Frames 0 … kFrames − 1 of the scene's animation through a module created with `inFlight` frames in
// flight: `overlapped` records frame k while frames k − 1 … k − inFlight + 1 may still run; otherwise
// every frame is submitted and waited for on its own.
AnimatedRun runFrames(const engine::Context& ctx, const std::string& path, uint32_t inFlight, bool overlapped,
                      engine::VulkanCallCounts* steadyCalls) {
  LoadedScene s;  // as loaded, for each run
  std::string error;
  EXPECT_TRUE(engine::loadSceneForRendering(path, s.scene, error)) << error;
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  engine::markAnimatedInstancesMovable(animation, s.scene);
  s.upload(ctx);
  const gpu::GpuCamera camera = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
  desc.framesInFlight = inFlight;
  desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
  gi::Settings settings;
  settings.method = gi::Method::Svgf;
  ScopedSession session(ctx);
  EXPECT_TRUE(tools::createModuleSession(ctx, s.gpu, {kSize, kSize}, settings, session, error, &desc)) << error;
  engine::FrameSlots slots = engine::createFrameSlots(ctx, error, inFlight);
  AnimatedRun run;
  const uint32_t warmup = inFlight + 2;
  engine::VulkanCallCounts atWarmup;
  for (uint32_t f = 0; f < kFrames && error.empty(); ++f) {
    if (f == warmup) {
      atWarmup = engine::vulkanCallCounts();
      run.moduleAllocationsAfterWarmup = gi::stats(session.module).deviceAllocations;
    }
    engine::animateScene(animation, float(f) / 30.0f, s.scene);
    if (overlapped) {
      engine::waitFrameSlot(ctx, slots, f, error);  // the frame inFlight back
      VkCommandBuffer cmd = engine::beginFrameSlot(ctx, slots, f, error);
      if (!cmd) break;
      recordUpdateOrFail(ctx, cmd, s.scene, s.gpu);
      tools::recordModuleFrame(ctx, cmd, session, s.scene, s.gpu, camera, camera, f);
      engine::submitFrameSlot(ctx, slots, f, error);
    } else {
      submitOrFail(ctx, [&](VkCommandBuffer cmd) {
        recordUpdateOrFail(ctx, cmd, s.scene, s.gpu);
        tools::recordModuleFrame(ctx, cmd, session, s.scene, s.gpu, camera, camera, f);
      });
    }
  }
  EXPECT_EQ(error, "");
  if (steadyCalls) *steadyCalls = engine::vulkanCallCounts() - atWarmup;
  vkDeviceWaitIdle(ctx.device);
  run.moduleAllocationsAtEnd = gi::stats(session.module).deviceAllocations;
  run.images = tools::readModuleImages(ctx, session);
  engine::destroyFrameSlots(ctx, slots);
  tools::destroyModuleSession(ctx, session);
  s.release();
  return run;
}

// The frames of the scene at `path`, kInFlight in flight and one at a time, checked as the file's comment says.
void expectFramesInFlightClean(const std::string& path) {
  engine::Context ctx;
  std::string error;
  ASSERT_TRUE(createSyncValidatedContext(ctx, error)) << error;
  engine::startCountingVulkanCalls();
  engine::VulkanCallCounts steady;
  const AnimatedRun overlapped = runFrames(ctx, path, kInFlight, true, &steady);
  const AnimatedRun alone = runFrames(ctx, path, kInFlight, false, nullptr);
  const uint64_t steadyFrames = kFrames - (kInFlight + 2);
  std::printf(
      "%llu steady frames, %u in flight: %llu fence waits, %llu idle waits, %llu creations; module "
      "allocations %llu then %llu\n",
      (unsigned long long)steadyFrames, kInFlight, (unsigned long long)steady.fenceWaits,
      (unsigned long long)steady.idleWaits, (unsigned long long)steady.creations,
      (unsigned long long)overlapped.moduleAllocationsAfterWarmup,
      (unsigned long long)overlapped.moduleAllocationsAtEnd);
  EXPECT_EQ(steady.fenceWaits, steadyFrames) << "one fence a frame: its slot's";
  EXPECT_EQ(steady.idleWaits, 0u);
  EXPECT_EQ(steady.creations, 0u);
  EXPECT_EQ(overlapped.moduleAllocationsAtEnd, overlapped.moduleAllocationsAfterWarmup);
  EXPECT_TRUE(sameBits(overlapped.images.indirect, alone.images.indirect)) << "each frame read its own pose's tables";
  EXPECT_TRUE(sameBits(overlapped.images.direct, alone.images.direct));
  EXPECT_EQ(ctx.validationMessages(), 0u) << "synchronization validation reported hazards";
  engine::destroyContext(ctx);
}

}  // namespace

TEST(FramesInFlight, AnimatedFramesThreeInFlightWaitOnOneFenceEachAndMatchFramesRunAlone) {
  expectFramesInFlightClean(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"));
}

// Issue 32: a skinned mesh posed on the device every frame (skinning.comp into the engine's buffers, handed
// over as device streams: gi::updateMeshVertices decodes them, refits the BVH and updates the BLAS in the
// frame's command buffer) keeps frames in flight apart the same way.
TEST(FramesInFlight, SkinnedFramesThreeInFlightWaitOnOneFenceEachAndMatchFramesRunAlone) {
  expectFramesInFlightClean(std::string(GI_ASSETS) + "/skinned_bar/skinned_bar.gltf");
}
