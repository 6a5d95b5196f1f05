// The module's persistent world-space hash map for path space filtering: GPU
// buffers (layout in shaders/shared/hash_grid.h), their descriptor set (set 2
// of the hpsf passes) and the three passes that use it.
#pragma once
#include <functional>

#include "compute_program.h"
#include "descriptors.h"
#include "resources.h"
#include "shared/hash_grid.h"

namespace gi {

struct HashGrid {
  uint32_t capacity = 0;
  engine::Buffer keys, accum, cells;
  engine::Buffer telemetry;  // host-visible HgTelemetry[1 + slots]: [0] is live, the rest per-frame copies
  engine::Image pixelCell;   // r32ui
  engine::DescriptorSet set;
  engine::ComputeProgram insert, resolve, lookup;
  uint64_t memoryBytes = 0;
  bool cleared = false;      // buffers zeroed on the GPU
};

// The buffers, image and set 2; `slots` telemetry copies for readback.
HashGrid createHashGrid(const engine::Context& ctx, uint32_t capacity, uint32_t width, uint32_t height, uint32_t slots);
// The insert/resolve/lookup programs: `layouts` are sets 0 and 1 (scene, frame).
void createHashGridPrograms(const engine::Context& ctx, HashGrid& grid, const VkDescriptorSetLayout layouts[2],
                            std::span<const uint32_t> spec);
void destroyHashGrid(const engine::Context& ctx, HashGrid& grid);

// Zeroes the map on first use and resets the live telemetry (transfer, then a barrier to compute).
void recordHashGridFrameStart(VkCommandBuffer cmd, HashGrid& grid);
// Copies the live telemetry into slot `slot` for readback (after the passes).
void recordHashGridTelemetryCopy(VkCommandBuffer cmd, HashGrid& grid, uint32_t slot);
gpu::HgTelemetry readHashGridTelemetry(const HashGrid& grid, uint32_t slot);

}  // namespace gi
