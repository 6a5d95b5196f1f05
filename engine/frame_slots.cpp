#include "frame_slots.h"

#include <algorithm>

namespace engine {

FrameSlots createFrameSlots(const Context& ctx, std::string& error, uint32_t count) {
  FrameSlots f;
  if (!error.empty()) return f;
  f.count = std::clamp(count, 1u, kMaxFramesInFlight);
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = f.count;
  bool made = VK_SUCCEEDED(error, "frame slots", vkAllocateCommandBuffers(ctx.device, &alloc, f.cmd));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  for (uint32_t slot = 0; made && slot < f.count; ++slot)
    made = VK_SUCCEEDED(error, "frame slots", vkCreateFence(ctx.device, &fence, nullptr, &f.done[slot]));
  if (!made) destroyFrameSlots(ctx, f);
  return f;
}

void destroyFrameSlots(const Context& ctx, FrameSlots& f) {
  for (VkFence d : f.done)
    if (d) vkDestroyFence(ctx.device, d, nullptr);
  if (f.cmd[0]) vkFreeCommandBuffers(ctx.device, ctx.commandPool, f.count, f.cmd);
  f = FrameSlots{};
}

bool waitFrameSlot(const Context& ctx, const FrameSlots& f, uint32_t frame, std::string& error) {
  return error.empty() && VK_SUCCEEDED(error, "waiting for a frame in flight",
                                       vkWaitForFences(ctx.device, 1, &f.done[frame % f.count], VK_TRUE, UINT64_MAX));
}

VkCommandBuffer beginFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame, std::string& error) {
  const uint32_t slot = frame % f.count;
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const char* what = "beginning a frame";
  const bool begun = error.empty() && VK_SUCCEEDED(error, what, vkResetFences(ctx.device, 1, &f.done[slot])) &&
                     VK_SUCCEEDED(error, what, vkResetCommandBuffer(f.cmd[slot], 0)) &&
                     VK_SUCCEEDED(error, what, vkBeginCommandBuffer(f.cmd[slot], &begin));
  return begun ? f.cmd[slot] : VK_NULL_HANDLE;
}

bool submitFrameSlot(const Context& ctx, FrameSlots& f, uint32_t frame, std::string& error, VkSemaphore wait,
                     VkPipelineStageFlags waitStage, VkSemaphore signal) {
  const uint32_t slot = frame % f.count;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = wait ? 1 : 0;
  submit.pWaitSemaphores = &wait;
  submit.pWaitDstStageMask = &waitStage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &f.cmd[slot];
  submit.signalSemaphoreCount = signal ? 1 : 0;
  submit.pSignalSemaphores = &signal;
  const char* what = "submitting a frame";
  return error.empty() && VK_SUCCEEDED(error, what, vkEndCommandBuffer(f.cmd[slot])) &&
         VK_SUCCEEDED(error, what, vkQueueSubmit(ctx.queue, 1, &submit, f.done[slot]));
}

}  // namespace engine
