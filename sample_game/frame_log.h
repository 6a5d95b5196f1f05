// Benchmark mode's CSV: one row per frame along the walkthrough with the
// G-buffer's and every module pass's GPU ms (a pass that runs several times a
// frame is summed), the module total, the CPU frame time, rays and spp, the
// method and whether another's programs were being readied.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include "gi/gi.h"

namespace demo {

struct FrameLog {
  std::ofstream file;
  std::vector<std::string> passColumns;  // fixed by the first row
  uint32_t rows = 0;
};

// False with a sentence naming the file when it cannot be written.
bool openFrameLog(FrameLog& log, const std::string& path, std::string& error);
// `method`: what the frame ran; `readying`: another method's programs were being readied meanwhile.
void writeFrameRow(FrameLog& log, uint32_t frame, double seconds, double cpuMs, double gbufferMs, const gi::FrameStats& stats,
                   const std::string& method, bool readying);

}  // namespace demo
