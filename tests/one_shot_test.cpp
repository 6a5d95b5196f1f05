// engine::submitAndWait records into the context's one command buffer and fence, reset for each submission,
// never a pair allocated and freed each time: Debian 12's validation layer (1.3.239) corrupts the heap when
// command buffers that carry debug labels are freed and allocated again at frame rate (issue 30;
// tests/label_stress.cpp, docs/RESULTS.md "Extremes"). A submission recorded inside another's `record`
// still gets a command buffer of its own.
#include "gpu_test.h"

#include <vector>

using OneShotTest = GpuTest;

TEST_F(OneShotTest, SubmissionsReuseTheContextsCommandBufferAndFence) {
  ASSERT_NE(ctx.oneShot, VK_NULL_HANDLE);
  ASSERT_NE(ctx.oneShotFence, VK_NULL_HANDLE);
  std::string error;
  std::vector<VkCommandBuffer> used;
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(engine::submitAndWait(
        ctx, [&](VkCommandBuffer cmd) { used.push_back(cmd); }, error))
        << error;
  EXPECT_EQ(used, std::vector<VkCommandBuffer>(3, ctx.oneShot));
  // Each submission waits for its own: the fence is signalled after the last.
  EXPECT_EQ(vkGetFenceStatus(ctx.device, ctx.oneShotFence), VK_SUCCESS);
}

TEST_F(OneShotTest, ASubmissionInsideAnotherGetsACommandBufferOfItsOwn) {
  std::string error;
  VkCommandBuffer outer = VK_NULL_HANDLE, inner = VK_NULL_HANDLE, after = VK_NULL_HANDLE;
  bool innerDone = false;
  ASSERT_TRUE(engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        outer = cmd;
        innerDone = engine::submitAndWait(
            ctx, [&](VkCommandBuffer nested) { inner = nested; }, error);
      },
      error))
      << error;
  EXPECT_TRUE(innerDone) << error;
  EXPECT_EQ(outer, ctx.oneShot);
  EXPECT_NE(inner, VK_NULL_HANDLE);
  EXPECT_NE(inner, outer);
  // The context's is free again once the outer submission is done.
  ASSERT_TRUE(engine::submitAndWait(
      ctx, [&](VkCommandBuffer cmd) { after = cmd; }, error))
      << error;
  EXPECT_EQ(after, ctx.oneShot);
}
