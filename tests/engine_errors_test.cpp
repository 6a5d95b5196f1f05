// The engine's one error style (engine/vk.h): a failed call is one sentence in `error`, naming what was
// being made, the Vulkan call and its result; nothing aborts; a call made while `error` holds a sentence
// does nothing, so a run of creations is checked once.
#include "descriptors.h"
#include "gpu_test.h"
#include "gpu_timer.h"
#include "resources.h"
#include "vulkan_call_counts.h"

TEST(EngineErrors, AFailedCallIsOneSentenceNamingWhatItMadeTheCallAndItsResult) {
  std::string error;
  EXPECT_TRUE(engine::vkSucceeded(VK_SUCCESS, "a buffer of 64 bytes", "vkCreateBuffer(device, &info)", error));
  EXPECT_EQ(error, "");
  EXPECT_FALSE(engine::vkSucceeded(VK_ERROR_OUT_OF_DEVICE_MEMORY, "a buffer of 64 bytes",
                                   "vkAllocateMemory(ctx.device, &alloc, nullptr, &memory)", error));
  EXPECT_EQ(error, "a buffer of 64 bytes: vkAllocateMemory failed with VK_ERROR_OUT_OF_DEVICE_MEMORY");
}

using EngineErrorsTest = GpuTest;

// No memory type among none: a sentence, not an abort.
TEST_F(EngineErrorsTest, NoMemoryTypeIsASentence) {
  std::string error;
  uint32_t type = 99;
  EXPECT_FALSE(engine::findMemoryType(ctx, 0u, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, type, error));
  EXPECT_EQ(type, 99u);
  EXPECT_NE(error.find("no Vulkan memory type has the flags 0x1"), std::string::npos) << error;
}

// After a failure, creations, submissions and read-backs make nothing, run nothing and keep the first
// sentence; destroying what they returned is harmless.
TEST_F(EngineErrorsTest, CallsAfterAFailureDoNothingAndKeepTheFirstSentence) {
  const std::string first = "the first failure";
  std::string error = first;
  engine::startCountingVulkanCalls();
  const engine::VulkanCallCounts before = engine::vulkanCallCounts();
  engine::Buffer buffer =
      engine::createBuffer(ctx, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, engine::MemoryKind::HostVisible, error);
  engine::Image image =
      engine::createImage(ctx, {8, 8}, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, error);
  const engine::Binding bindings[] = {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
  engine::DescriptorSet set = engine::createDescriptorSet(ctx, bindings, error);
  engine::GpuTimer timer = engine::createGpuTimer(ctx, error, 2);
  bool recorded = false;
  EXPECT_FALSE(engine::submitAndWait(
      ctx, [&](VkCommandBuffer) { recorded = true; }, error));
  EXPECT_TRUE(engine::readbackImage(ctx, image, VK_IMAGE_LAYOUT_GENERAL, 16, error).empty());
  const engine::VulkanCallCounts made = engine::vulkanCallCounts() - before;
  EXPECT_EQ(made.creations, 0u);
  EXPECT_EQ(made.fenceWaits, 0u);
  EXPECT_FALSE(recorded);
  EXPECT_EQ(buffer.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffer.mapped, nullptr);
  EXPECT_EQ(image.image, VK_NULL_HANDLE);
  EXPECT_EQ(set.set, VK_NULL_HANDLE);
  EXPECT_EQ(timer.pool, VK_NULL_HANDLE);
  EXPECT_EQ(error, first);
  engine::destroyGpuTimer(ctx, timer);
  engine::destroyDescriptorSet(ctx, set);
  engine::destroyImage(ctx, image);
  engine::destroyBuffer(ctx, buffer);
}

// A frame that begins more passes than its timer has room for is labelled and run; reading its times
// says so instead of stopping the process.
TEST_F(EngineErrorsTest, AnOverfullTimerIsReportedWhenRead) {
  std::string error;
  engine::GpuTimer timer = engine::createGpuTimer(ctx, error, 1);
  ASSERT_EQ(error, "");
  EXPECT_TRUE(engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        engine::beginPass(ctx, cmd, timer, "first");
        engine::endPass(ctx, cmd, timer);
        engine::beginPass(ctx, cmd, timer, "second");
        engine::endPass(ctx, cmd, timer);
      },
      error))
      << error;
  EXPECT_TRUE(engine::readPassTimes(ctx, timer, error).empty());
  EXPECT_EQ(error, "the GPU timer has room for 1 passes a frame and this frame began 2");
  engine::resetGpuTimer(ctx, timer);  // a new frame within its room reads again
  error.clear();
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    engine::beginPass(ctx, cmd, timer, "only");
    engine::endPass(ctx, cmd, timer);
  });
  const std::vector<engine::PassTime> times = engine::readPassTimes(ctx, timer, error);
  EXPECT_EQ(error, "");
  ASSERT_EQ(times.size(), 1u);
  EXPECT_EQ(times[0].name, "only");
  engine::destroyGpuTimer(ctx, timer);
}
