#include "frame_slots.h"

namespace engine {

FrameSlots createFrameSlots(const Context& ctx) {
  FrameSlots f;
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = kFramesInFlight;
  VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, f.cmd));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  for (VkFence& d : f.done) VK_CHECK(vkCreateFence(ctx.device, &fence, nullptr, &d));
  return f;
}

void destroyFrameSlots(const Context& ctx, FrameSlots& f) {
  for (VkFence d : f.done)
    if (d) vkDestroyFence(ctx.device, d, nullptr);
  if (f.cmd[0]) vkFreeCommandBuffers(ctx.device, ctx.commandPool, kFramesInFlight, f.cmd);
  f = FrameSlots{};
}

void waitFrameSlot(const Context& ctx, const FrameSlots& f, uint32_t frame) {
  VK_CHECK(vkWaitForFences(ctx.device, 1, &f.done[frame % kFramesInFlight], VK_TRUE, UINT64_MAX));
}

VkCommandBuffer beginFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame) {
  const uint32_t slot = frame % kFramesInFlight;
  VK_CHECK(vkResetFences(ctx.device, 1, &f.done[slot]));
  VK_CHECK(vkResetCommandBuffer(f.cmd[slot], 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(f.cmd[slot], &begin));
  return f.cmd[slot];
}

void submitFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame, VkSemaphore wait, VkPipelineStageFlags waitStage,
                     VkSemaphore signal) {
  const uint32_t slot = frame % kFramesInFlight;
  VK_CHECK(vkEndCommandBuffer(f.cmd[slot]));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = wait ? 1 : 0;
  submit.pWaitSemaphores = &wait;
  submit.pWaitDstStageMask = &waitStage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &f.cmd[slot];
  submit.signalSemaphoreCount = signal ? 1 : 0;
  submit.pSignalSemaphores = &signal;
  VK_CHECK(vkQueueSubmit(ctx.queue, 1, &submit, f.done[slot]));
}

void waitOtherFrameSlots(const Context& ctx, const FrameSlots& f, uint32_t frame) {
  for (uint32_t slot = 0; slot < kFramesInFlight; ++slot)
    if (slot != frame % kFramesInFlight) VK_CHECK(vkWaitForFences(ctx.device, 1, &f.done[slot], VK_TRUE, UINT64_MAX));
}

}  // namespace engine
