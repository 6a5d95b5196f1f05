// Benchmark mode's CSV: one row per frame along the walkthrough with the
// G-buffer's and every module pass's GPU ms (a pass that runs several times a
// frame is summed), the module total, the CPU frame time, rays and spp, the
// method and whether another's programs were being readied; the frame's own
// fence and idle waits and Vulkan creations (engine/vulkan_call_counts.h) and
// the module's device allocations.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include "gi/gi.h"
#include "vulkan_call_counts.h"

namespace demo {

struct FrameLog {
  std::ofstream file;
  std::vector<std::string> passColumns;  // fixed by the first row
  uint32_t rows = 0;
};

// False with a sentence naming the file when it cannot be written.
bool openFrameLog(FrameLog& log, const std::string& path, std::string& error);
// What a frame ran beside its stats: the method, whether another method's programs were being readied
// meanwhile, and the Vulkan calls the demo made while recording it.
struct FrameFacts {
  std::string method;
  bool readying = false;
  engine::VulkanCallCounts calls;
};
void writeFrameRow(FrameLog& log, uint32_t frame, double seconds, double cpuMs, double gbufferMs,
                   const gi::FrameStats& stats, const FrameFacts& facts);

}  // namespace demo
