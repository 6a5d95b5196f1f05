#include "headless_frames.h"

namespace demo {

HeadlessFrames createHeadlessFrames(const engine::Context& ctx) {
  HeadlessFrames f;
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = kHeadlessFramesInFlight;
  VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, f.cmd));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  for (VkFence& d : f.done) VK_CHECK(vkCreateFence(ctx.device, &fence, nullptr, &d));
  return f;
}

void destroyHeadlessFrames(const engine::Context& ctx, HeadlessFrames& f) {
  for (VkFence d : f.done)
    if (d) vkDestroyFence(ctx.device, d, nullptr);
  if (f.cmd[0]) vkFreeCommandBuffers(ctx.device, ctx.commandPool, kHeadlessFramesInFlight, f.cmd);
  f = HeadlessFrames{};
}

VkCommandBuffer beginHeadlessFrame(const engine::Context& ctx, HeadlessFrames& f, uint32_t frame) {
  const uint32_t slot = frame % kHeadlessFramesInFlight;
  VK_CHECK(vkWaitForFences(ctx.device, 1, &f.done[slot], VK_TRUE, UINT64_MAX));
  VK_CHECK(vkResetFences(ctx.device, 1, &f.done[slot]));
  VK_CHECK(vkResetCommandBuffer(f.cmd[slot], 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(f.cmd[slot], &begin));
  return f.cmd[slot];
}

void submitHeadlessFrame(const engine::Context& ctx, HeadlessFrames& f, uint32_t frame) {
  const uint32_t slot = frame % kHeadlessFramesInFlight;
  VK_CHECK(vkEndCommandBuffer(f.cmd[slot]));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &f.cmd[slot];
  VK_CHECK(vkQueueSubmit(ctx.queue, 1, &submit, f.done[slot]));
}

void waitForOtherHeadlessFrames(const engine::Context& ctx, const HeadlessFrames& f, uint32_t frame) {
  for (uint32_t slot = 0; slot < kHeadlessFramesInFlight; ++slot)
    if (slot != frame % kHeadlessFramesInFlight)
      VK_CHECK(vkWaitForFences(ctx.device, 1, &f.done[slot], VK_TRUE, UINT64_MAX));
}

}  // namespace demo
