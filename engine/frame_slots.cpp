#include "frame_slots.h"

#include <algorithm>

namespace engine {

FrameSlots createFrameSlots(const Context& ctx, uint32_t count) {
  FrameSlots f;
  f.count = std::clamp(count, 1u, kMaxFramesInFlight);
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = f.count;
  VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, f.cmd));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  for (uint32_t slot = 0; slot < f.count; ++slot) VK_CHECK(vkCreateFence(ctx.device, &fence, nullptr, &f.done[slot]));
  return f;
}

void destroyFrameSlots(const Context& ctx, FrameSlots& f) {
  for (VkFence d : f.done)
    if (d) vkDestroyFence(ctx.device, d, nullptr);
  if (f.cmd[0]) vkFreeCommandBuffers(ctx.device, ctx.commandPool, f.count, f.cmd);
  f = FrameSlots{};
}

void waitFrameSlot(const Context& ctx, const FrameSlots& f, uint32_t frame) {
  VK_CHECK(vkWaitForFences(ctx.device, 1, &f.done[frame % f.count], VK_TRUE, UINT64_MAX));
}

VkCommandBuffer beginFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame) {
  const uint32_t slot = frame % f.count;
  VK_CHECK(vkResetFences(ctx.device, 1, &f.done[slot]));
  VK_CHECK(vkResetCommandBuffer(f.cmd[slot], 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(f.cmd[slot], &begin));
  return f.cmd[slot];
}

void submitFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame, VkSemaphore wait,
                     VkPipelineStageFlags waitStage, VkSemaphore signal) {
  const uint32_t slot = frame % f.count;
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

}  // namespace engine
