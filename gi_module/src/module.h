// The module's internal state. Passes are free functions over it; the frame
// (module.cpp) calls them in order like a script.
#pragma once
#include "compute_program.h"
#include "descriptors.h"
#include "gi/gi.h"
#include "resources.h"
#include "hash_grid.h"
#include "screen_filters.h"
#include "shared/gi_frame.h"

namespace gi {

inline constexpr uint32_t kFramesInFlight = 2;  // timestamp/counter slots, so a frame's numbers survive the next
inline constexpr uint32_t kMaxPasses = 16;

struct Module {
  engine::Context ctx;  // device handles only: the module never submits
  ModuleDesc desc;
  Settings settings;

  engine::Image direct, indirect, composite;       // outputs
  engine::Image historyDirect, historyIndirect;    // temporal accumulation (raw)
  engine::Image noisyIndirect;                     // demodulated indirect before filtering
  engine::Image guidance, position, debug;         // filter guidance, world position, filter debug/temp
  engine::Image aafParams, aafSum;                 // AAF per-pixel z_min, z_max, samples, β; sample sums
  engine::Image aafGlossy, aafGlossyEdge;          // AAF specular terms (1×1 unless the scene has glossy materials)
  ScreenFilters filters;                           // created on first use of a filter method
  HashGrid hash;                                   // created on first use of hpsf; persists across frames
  engine::Buffer frameConstants;                   // host-visible GiFrameConstants
  engine::Buffer counters;                         // host-visible GiCounters[kFramesInFlight]
  engine::DescriptorSet frameSet;
  GBufferViews boundGBuffer{};                     // views currently written into frameSet

  engine::ComputeProgram rawTrace, composite_, guidancePass, supersample, aafSample, aafAdaptive;

  VkQueryPool timestamps = VK_NULL_HANDLE;         // 2 per pass per slot
  std::vector<std::string> passNames[kFramesInFlight];
  uint32_t slotFrameIndex[kFramesInFlight] = {};
  bool slotRecorded[kFramesInFlight] = {};
  uint32_t slotHistory[kFramesInFlight] = {};
  uint32_t slotSpp[kFramesInFlight] = {};
  Method slotMethod[kFramesInFlight] = {};

  bool imagesInitialised = false;
  uint32_t historyLength = 0;                      // frames in the history images
  gpu::GpuCamera historyCamera{};                  // camera the history was gathered with
  FrameStats lastStats;
};

// Pass helpers (module.cpp).
PassHooks passHooks(Module& m, uint32_t slot);
void beginPass(Module& m, VkCommandBuffer cmd, uint32_t slot, const char* name);
void endPass(Module& m, VkCommandBuffer cmd, uint32_t slot);
void computeToComputeBarrier(VkCommandBuffer cmd);

}  // namespace gi
