// The hash map on the GPU under collisions: no lost update below capacity,
// and an exact failed-insert count beyond it.
#include <cstring>
#include <map>

#include "gpu_test.h"
#include "hash_grid.h"
#include "hash_stress.comp.h"

class HashGridTest : public GpuTest {};

TEST_F(HashGridTest, InsertAndFindUnderLoadLoseNothingBelowCapacity) {
  const uint32_t capacity = 1024, repeats = 3;
  engine::DescriptorSet empty = engine::createDescriptorSet(ctx, {});
  gi::HashGrid grid = gi::createHashGrid(ctx, capacity, 1, 8, 8, 1, false);
  VkDescriptorSetLayout all[] = {empty.layout, empty.layout, grid.set.layout};
  struct Push {
    uint32_t capacity, window, keyCount, repeats;
  };
  engine::ComputeProgram stress = engine::createComputeProgram(ctx, spv_hash_stress_comp, all, sizeof(Push), {64, 1});
  VkDescriptorSet sets[] = {empty.set, empty.set, grid.set.set};
  for (double load : {0.5, 0.9, 1.0, 1.25}) {
    uint32_t keys = uint32_t(load * capacity);
    grid.cleared = false;  // start from an empty map
    engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
      gi::recordHashGridFrameStart(cmd, grid, 0);
      // The probe window spans the table, so any free slot can be found.
      engine::dispatch(cmd, stress, sets, {keys * repeats, 1}, Push{capacity, capacity, keys, repeats});
      gi::recordHashGridTelemetryCopy(cmd, grid, 0);
    });
    gpu::HgTelemetry t = gi::readHashGridTelemetry(grid, 0);
    // Read the table back.
    engine::Buffer staging = engine::createBuffer(ctx, grid.keys.size + grid.accum.size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                  engine::MemoryKind::HostVisible);
    engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) {
      VkBufferCopy a{0, 0, grid.keys.size}, b{0, grid.keys.size, grid.accum.size};
      vkCmdCopyBuffer(cmd, grid.keys.buffer, staging.buffer, 1, &a);
      vkCmdCopyBuffer(cmd, grid.accum.buffer, staging.buffer, 1, &b);
    });
    const auto* k = static_cast<const uint32_t*>(staging.mapped);
    const auto* acc = reinterpret_cast<const gpu::HgAccum*>(static_cast<const std::byte*>(staging.mapped) + grid.keys.size);
    std::map<uint32_t, uint32_t> counts;
    uint32_t occupied = 0;
    for (uint32_t s = 0; s < capacity; ++s) {
      if (k[s] == gpu::HG_EMPTY_KEY) continue;
      ++occupied;
      EXPECT_EQ(counts.count(k[s]), 0u) << "a key stored twice";
      counts[k[s]] = acc[s].count;
      EXPECT_EQ(acc[s].count, repeats) << "load " << load << ": a lost or extra update";
      EXPECT_EQ(acc[s].r, repeats * gpu::hgToFixed(1.0f));
      EXPECT_EQ(acc[s].g, repeats * gpu::hgToFixed(2.0f));
    }
    uint32_t stored = std::min(keys, capacity);
    EXPECT_EQ(occupied, stored) << "load " << load;
    EXPECT_EQ(t.failedInserts, (keys - stored) * repeats) << "load " << load;
    engine::destroyBuffer(ctx, staging);
  }
  engine::destroyComputeProgram(ctx, stress);
  gi::destroyHashGrid(ctx, grid);
  engine::destroyDescriptorSet(ctx, empty);
}
