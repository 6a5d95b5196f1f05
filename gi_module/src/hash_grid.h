// The module's persistent world-space hash map for path space filtering: GPU
// buffers (layout in shaders/shared/hash_grid.h), their descriptor set (set 2
// of the hpsf passes) and the three passes that use it.
#pragma once
#include <functional>

#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "shared/hash_grid.h"

namespace gi {

struct HashGrid {
  uint32_t capacity = 0;     // slots per table
  uint32_t tables = 1;       // 2 for strict eviction (swapped every frame), 1 for aging
  vk::Buffer keys, accum, cells;
  vk::Buffer telemetry;      // host-visible HgTelemetry[1 + slots]: [0] is live, the rest per-frame copies
  vk::Buffer walks;          // HgWalk per pixel of the largest render size (anhpsf), else one placeholder
  uint32_t walkPixels = 0;   // pixels with a walk slot (0: the placeholder)
  vk::DescriptorSets set;    // one set
  vk::ComputeProgram insert, paths, validate, resolve, lookup;  // paths: nhpsf/anhpsf; validate: probes (built on first use)
  uint64_t memoryBytes = 0;
  bool cleared = false;      // buffers zeroed on the GPU
  bool walksCleared = false; // continued paths reset (a new render size restarts them)
  bool forgetLight = false;  // gi::invalidate(LightsChanged): the next resolve restarts every cell's mean
};

// The buffers (`tables` tables of `capacity` slots) and set 2; `slots`
// telemetry copies for readback; a walk per pixel when `walks` (anhpsf).
// `width` × `height` is the largest render size: smaller ones keep the map.
vk::Status createHashGrid(vk::Device& device, uint32_t capacity, uint32_t tables, uint32_t width, uint32_t height,
                          uint32_t slots, bool walks, HashGrid& out);
// The programs the mode needs (insert for hpsf, paths for nhpsf/anhpsf;
// validate where stale radiance is checked; resolve and lookup always):
// `layouts` are sets 0 and 1 (scene, frame).
vk::Status ensureHashGridPrograms(const vk::Device& device, HashGrid& grid, const VkDescriptorSetLayout layouts[2],
                                  std::span<const uint32_t> spec, uint32_t mode, bool validates, uint32_t traversal);
void destroyHashGrid(vk::Device& device, HashGrid& grid);

// First slot of the table written in frame `frameIndex`, and of the one it reads as the last frame.
uint32_t hashTableBase(const HashGrid& grid, uint32_t frameIndex);
uint32_t previousHashTableBase(const HashGrid& grid, uint32_t frameIndex);
// Zeroes the map on first use, and with two tables the one this frame
// writes; resets the live telemetry (transfer, then a barrier to compute).
void recordHashGridFrameStart(const vk::Device& device, VkCommandBuffer cmd, HashGrid& grid, uint32_t frameIndex);
// Copies the live telemetry into slot `slot` for readback (after the passes).
void recordHashGridTelemetryCopy(const vk::Device& device, VkCommandBuffer cmd, HashGrid& grid, uint32_t slot);
gpu::HgTelemetry readHashGridTelemetry(const HashGrid& grid, uint32_t slot);

}  // namespace gi
