// GPU timestamps around every pass, with a debug label of the same name so
// captures and timings read alike. Reset before recording a frame; read after
// its fence has signalled.
#pragma once
#include "context.h"

#include <string>
#include <vector>

namespace engine {

struct PassTime {
  std::string name;
  double ms = 0.0;
};

struct GpuTimer {
  VkQueryPool pool = VK_NULL_HANDLE;
  uint32_t capacity = 0;  // passes per frame
  std::vector<std::string> names;
  std::vector<uint32_t> open;  // passes begun but not ended (kUntimed: past capacity)
  uint32_t untimed = 0;        // passes begun this frame beyond `capacity`: labelled, not timed
  double nsPerTick = 1.0;
};

// Errors as in vk.h: an empty timer and `error`.
GpuTimer createGpuTimer(const Context& ctx, std::string& error, uint32_t maxPasses = 64);
void destroyGpuTimer(const Context& ctx, GpuTimer& timer);
void resetGpuTimer(const Context& ctx, GpuTimer& timer);  // host-side, before recording
void beginPass(const Context& ctx, VkCommandBuffer cmd, GpuTimer& timer, const char* name);
void endPass(const Context& ctx, VkCommandBuffer cmd, GpuTimer& timer);
// A barrier placed right after a pass's first timestamp. Without it lavapipe
// stamps the start only once the pass's work has run (measured: a 42 ms trace
// read as 0.1 ms); on GPUs it costs one pipeline drain per pass.
void timestampFence(VkCommandBuffer cmd);
// Waits for nothing: call once the frame's work has completed. Empty, with `error`, when the
// query results cannot be read or the frame began more passes than the timer has room for.
std::vector<PassTime> readPassTimes(const Context& ctx, const GpuTimer& timer, std::string& error);

}  // namespace engine
