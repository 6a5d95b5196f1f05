// The module's persistent world-space hash map for path space filtering: GPU
// buffers (layout in shaders/shared/hash_grid.h) and their descriptor set (set 2
// of the hash methods' passes, whose programs the module holds: programs.h).
#pragma once
#include <functional>

#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "shared/hash_grid.h"

namespace gi {

struct HashGrid {
  uint32_t capacity = 0;                  // slots per table
  uint32_t tables = 1;                    // 2 for strict eviction (swapped every frame), 1 for aging
  vk::Buffer keys, accum, counts, cells;  // HG_BINDING_KEYS, _ACCUM, _COUNTS, _CELLS
  vk::Buffer telemetry;                   // host-visible HgTelemetry[1 + slots]: [0] is live, the rest per-frame copies
  vk::Buffer walks;         // HgWalkRecord per pixel of the largest render size (anhpsf), else one placeholder
  uint32_t walkPixels = 0;  // pixels with a walk slot (0: the placeholder)
  vk::DescriptorSets set;   // one set, of the module's set-2 layout
  uint64_t memoryBytes = 0;
  bool cleared = false;       // buffers zeroed on the GPU
  bool walksCleared = false;  // continued paths reset (a new render size restarts them)
  bool forgetLight = false;   // gi::invalidate(LightsChanged): the next resolve restarts every cell's mean
};

// Set 2's layout (one per module: every grid's set has it).
vk::Status createHashGridLayout(const vk::Device& device, VkDescriptorSetLayout& out);
// The buffers (`tables` tables of `capacity` slots) and set 2 (of `layout`);
// `slots` telemetry copies for readback; a walk per pixel when `walks` (anhpsf).
// `width` × `height` is the largest render size: smaller ones keep the map.
vk::Status createHashGrid(vk::Device& device, VkDescriptorSetLayout layout, uint32_t capacity, uint32_t tables,
                          uint32_t width, uint32_t height, uint32_t slots, bool walks, HashGrid& out);
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
