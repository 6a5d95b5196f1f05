// Frames in flight: a command buffer and a fence per slot, frame N in slot
// N mod count. Waiting on a slot waits for the frame recorded count frames
// earlier; the window, the headless demo and the
// embedding example all record this way.
#pragma once
#include "context.h"

#include <string>

namespace engine {

inline constexpr uint32_t kFramesInFlight = 2;     // the window's and the demo's
inline constexpr uint32_t kMaxFramesInFlight = 4;  // gi::ModuleDesc::framesInFlight's range

struct FrameSlots {
  VkCommandBuffer cmd[kMaxFramesInFlight] = {};
  VkFence done[kMaxFramesInFlight] = {};
  uint32_t count = 0;  // slots, [1, kMaxFramesInFlight]
};

// Errors as in vk.h: false (or an empty FrameSlots / a null command buffer) with `error` set.
FrameSlots createFrameSlots(const Context& ctx, std::string& error, uint32_t count = kFramesInFlight);
void destroyFrameSlots(const Context& ctx, FrameSlots& slots);
// Waits for the frame that last used frame `frame`'s slot.
bool waitFrameSlot(const Context& ctx, const FrameSlots& slots, uint32_t frame, std::string& error);
// Resets the slot's fence and begins its command buffer (after waitFrameSlot).
VkCommandBuffer beginFrameSlot(const Context& ctx, FrameSlots& slots, uint32_t frame, std::string& error);
// Ends and submits the slot's command buffer, signalling its fence; optionally
// waiting on and signalling semaphores (a swapchain's).
bool submitFrameSlot(const Context& ctx, FrameSlots& slots, uint32_t frame, std::string& error,
                     VkSemaphore wait = VK_NULL_HANDLE, VkPipelineStageFlags waitStage = 0,
                     VkSemaphore signal = VK_NULL_HANDLE);

}  // namespace engine
