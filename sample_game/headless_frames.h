// The demo's frames without a window, two in flight like the windowed loop:
// a command buffer and a fence per slot. begin waits for the frame recorded
// two before (its numbers and its display image are then final).
#pragma once
#include "context.h"

namespace demo {

inline constexpr uint32_t kHeadlessFramesInFlight = 2;

struct HeadlessFrames {
  VkCommandBuffer cmd[kHeadlessFramesInFlight] = {};
  VkFence done[kHeadlessFramesInFlight] = {};
};

HeadlessFrames createHeadlessFrames(const engine::Context& ctx);
void destroyHeadlessFrames(const engine::Context& ctx, HeadlessFrames& frames);
// Waits for the frame that last used frame `frame`'s slot, then begins its command buffer.
VkCommandBuffer beginHeadlessFrame(const engine::Context& ctx, HeadlessFrames& frames, uint32_t frame);
void submitHeadlessFrame(const engine::Context& ctx, HeadlessFrames& frames, uint32_t frame);
// Waits for every frame but `frame` (being recorded): before host writes that frames in flight read.
void waitForOtherHeadlessFrames(const engine::Context& ctx, const HeadlessFrames& frames, uint32_t frame);

}  // namespace demo
