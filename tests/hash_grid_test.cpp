// The hash map on the GPU under collisions: no lost update below capacity,
// an exact failed-insert count beyond it, and eviction that keeps probe
// chains whole and leaves nothing behind.
#include <algorithm>
#include <cstring>
#include <map>

#include "gpu_test.h"
#include "module_device.h"
#include "hash_grid.h"
#include "hash_stress.comp.h"
#include "shared/hash_stress.h"

namespace {

using StressPush = gpu::HgStressPush;
constexpr uint32_t kInsert = gpu::HG_STRESS_INSERT, kEvict = gpu::HG_STRESS_EVICT, kTidy = gpu::HG_STRESS_TIDY,
                   kClaim = gpu::HG_STRESS_CLAIM;

}  // namespace

class HashGridTest : public GpuTest {
 protected:
  engine::DescriptorSet empty;
  VkDescriptorSetLayout gridLayout = VK_NULL_HANDLE;
  gi::HashGrid grid;
  engine::ComputeProgram stress;
  gi::vk::Device dev;

  void make(uint32_t capacity) {
    dev = openModuleDevice(ctx);
    std::string error;
    empty = engine::createDescriptorSet(ctx, {}, error);
    ASSERT_FALSE(gi::createHashGridLayout(dev, gridLayout));
    ASSERT_FALSE(gi::createHashGrid(dev, gridLayout, capacity, 1, 8, 8, 1, false, grid));
    VkDescriptorSetLayout all[] = {empty.layout, empty.layout, gridLayout};
    stress = engine::createComputeProgram(ctx, spv_hash_stress_comp, all, sizeof(StressPush), {64, 1}, error);
    ASSERT_EQ(error, "");
  }
  void TearDown() override {
    engine::destroyComputeProgram(ctx, stress);
    gi::destroyHashGrid(dev, grid);
    if (gridLayout) dev.fn.vkDestroyDescriptorSetLayout(dev.device, gridLayout, dev.allocator);
    gi::vk::closeDevice(dev);
    engine::destroyDescriptorSet(ctx, empty);
    GpuTest::TearDown();
  }
  // One dispatch of hash_stress.comp (threads: keys × repeats, or every slot for kTidy and kClaim).
  void run(const StressPush& push) {
    VkDescriptorSet sets[] = {empty.set, empty.set, grid.set[0]};
    const bool everySlot = push.mode == kTidy || push.mode == kClaim;
    uint32_t threads = everySlot ? push.capacity : push.keyCount * (push.mode == kInsert ? push.repeats : 1u);
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      gi::recordHashGridFrameStart(dev, cmd, grid, 0);
      engine::dispatch(ctx, cmd, stress, sets, {threads, 1}, push);
      gi::recordHashGridTelemetryCopy(dev, cmd, grid, 0);
    });
  }
  // The keys, sums and sample counts as the GPU holds them.
  void read(std::vector<uint32_t>& keys, std::vector<gpu::HgAccum>& accum, std::vector<uint32_t>& samples) {
    std::string error;
    const VkDeviceSize bytes = grid.keys.size + grid.accum.size + grid.counts.size;
    engine::Buffer staging =
        engine::createBuffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, engine::MemoryKind::HostVisible, error);
    ASSERT_EQ(error, "");
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      VkBufferCopy a{0, 0, grid.keys.size}, b{0, grid.keys.size, grid.accum.size},
          c{0, grid.keys.size + grid.accum.size, grid.counts.size};
      vkCmdCopyBuffer(cmd, grid.keys.buffer, staging.buffer, 1, &a);
      vkCmdCopyBuffer(cmd, grid.accum.buffer, staging.buffer, 1, &b);
      vkCmdCopyBuffer(cmd, grid.counts.buffer, staging.buffer, 1, &c);
    });
    keys.assign(grid.capacity, 0);
    accum.assign(grid.capacity, {});
    samples.assign(grid.capacity, 0);
    const std::byte* mapped = static_cast<const std::byte*>(staging.mapped);
    std::memcpy(keys.data(), mapped, grid.keys.size);
    std::memcpy(accum.data(), mapped + grid.keys.size, grid.accum.size);
    std::memcpy(samples.data(), mapped + grid.keys.size + grid.accum.size, grid.counts.size);
    engine::destroyBuffer(ctx, staging);
  }
  static uint32_t keyOf(uint32_t k) { return gpu::hgVerificationKey(gpu::HgDescriptor{int(k), 1, -1, 0, 0}); }
};

TEST_F(HashGridTest, InsertAndFindUnderLoadLoseNothingBelowCapacity) {
  const uint32_t capacity = 1024, repeats = 3;
  make(capacity);
  for (double load : {0.5, 0.9, 1.0, 1.25}) {
    uint32_t keys = uint32_t(load * capacity);
    grid.cleared = false;  // start from an empty map
    // The probe window spans the table, so any free slot can be found.
    run({capacity, capacity, keys, repeats, kInsert, 0, 0, 1, 0});
    gpu::HgTelemetry t = gi::readHashGridTelemetry(grid, 0);
    std::vector<uint32_t> k;
    std::vector<gpu::HgAccum> acc;
    std::vector<uint32_t> samples;
    read(k, acc, samples);
    std::map<uint32_t, uint32_t> counts;
    uint32_t occupied = 0;
    for (uint32_t s = 0; s < capacity; ++s) {
      if (k[s] == gpu::HG_EMPTY_KEY) continue;
      ++occupied;
      EXPECT_EQ(counts.count(k[s]), 0u) << "a key stored twice";
      counts[k[s]] = samples[s];
      EXPECT_EQ(samples[s], repeats) << "load " << load << ": a lost or extra update";
      EXPECT_EQ(acc[s].r, repeats * gpu::hgToFixed(1.0f));
      EXPECT_EQ(acc[s].g, repeats * gpu::hgToFixed(2.0f));
    }
    uint32_t stored = std::min(keys, capacity);
    EXPECT_EQ(occupied, stored) << "load " << load;
    EXPECT_EQ(t.failedInserts, (keys - stored) * repeats) << "load " << load;
  }
}

// Deferred claims (HgPush::deferredClaims): which keys get slots follows from the bids, not from the order
// the threads ran in. Forty keys share one start slot and a window of 16 slots: each round they bid for the
// first free slot, all with priority 0, and the largest key bidding gets it, so after 16 rounds slot s holds the
// (s+1)-th largest key, with every sample of the rounds after its claim, and the other 24 keys are turned
// away. First come, first served (the claims inserts make at once) fills the window in the threads' order.
TEST_F(HashGridTest, DeferredClaimsGiveAFullWindowToTheLargestKeysInAnyOrder) {
  const uint32_t capacity = 1024, window = 16, keys = 40, repeats = 3;
  make(capacity);
  std::vector<uint32_t> largest;
  for (uint32_t k = 0; k < keys; ++k) largest.push_back(keyOf(k));
  std::sort(largest.rbegin(), largest.rend());
  for (uint32_t round = 0; round < window; ++round) {
    run({capacity, window, keys, repeats, kInsert, 0, 1, 1, 1});
    EXPECT_EQ(gi::readHashGridTelemetry(grid, 0).failedInserts, 0u) << "round " << round << ": a slot is still free";
    run({capacity, window, 0, 1, kClaim, 0, 1, 0, 1});
  }
  run({capacity, window, keys, repeats, kInsert, 0, 1, 1, 1});
  EXPECT_EQ(gi::readHashGridTelemetry(grid, 0).failedInserts, (keys - window) * repeats);
  std::vector<uint32_t> k;
  std::vector<gpu::HgAccum> acc;
  std::vector<uint32_t> samples;
  read(k, acc, samples);
  for (uint32_t s = 0; s < capacity; ++s) {
    if (s >= window) {
      EXPECT_EQ(acc[s].lum2, 0u) << "slot " << s << ": a bid left behind";
      EXPECT_EQ(k[s], gpu::HG_EMPTY_KEY) << "slot " << s << " is outside the window";
      continue;
    }
    EXPECT_EQ(k[s], largest[s]) << "slot " << s;
    EXPECT_EQ(samples[s], repeats * (window - s)) << "slot " << s << ": the samples since its claim";
  }
}

// Aging eviction from the middle of a probe chain: the keys further along
// must stay reachable (an emptied slot would end every search there, and the
// next insert of a later key would store it a second time). Eight keys share
// one start slot; the fourth is evicted; inserting the other seven again must
// find their own cells (count 2) and store no key twice.
TEST_F(HashGridTest, EvictingFromTheMiddleOfAChainKeepsTheLaterKeysReachable) {
  const uint32_t capacity = 1024, chain = 8;
  make(capacity);
  grid.cleared = false;
  for (uint32_t k = 0; k < chain; ++k) run({capacity, 16, 1, 1, kInsert, k, 1, 1, 0});  // key k in slot k
  run({capacity, 16, 1, 1, kEvict, 3, 1, 0, 0});                                        // key 3 goes
  std::vector<uint32_t> keys;
  std::vector<gpu::HgAccum> accum;
  std::vector<uint32_t> samples;
  read(keys, accum, samples);
  EXPECT_EQ(keys[3], gpu::HG_TOMBSTONE_KEY) << "the evicted slot still carries the chain";
  EXPECT_EQ(samples[3], 0u);
  for (uint32_t k : {0u, 1u, 2u, 4u, 5u, 6u, 7u}) run({capacity, 16, 1, 1, kInsert, k, 1, 1, 0});
  read(keys, accum, samples);
  std::map<uint32_t, int> seen;
  for (uint32_t s = 0; s < capacity; ++s)
    if (keys[s] != gpu::HG_EMPTY_KEY && keys[s] != gpu::HG_TOMBSTONE_KEY) ++seen[keys[s]];
  for (uint32_t k : {0u, 1u, 2u, 4u, 5u, 6u, 7u}) {
    EXPECT_EQ(seen[keyOf(k)], 1) << "key " << k << " stored " << seen[keyOf(k)] << " times";
    EXPECT_EQ(keys[k], keyOf(k));
    EXPECT_EQ(samples[k], 2u) << "key " << k << " did not find its own cell";
  }
  EXPECT_EQ(seen.count(keyOf(3)), 0u);
  // A new key reclaims the tombstone (the first free slot of its chain).
  run({capacity, 16, 1, 1, kInsert, 100, 1, 1, 0});
  read(keys, accum, samples);
  EXPECT_EQ(keys[3], keyOf(100));
  EXPECT_EQ(samples[3], 1u);
}

// An evicted cell's sums go with it: the next key to claim its slot starts
// from nothing. Light added to a sample already counted (count 0, a continued
// path) finds an existing cell or nothing: it never makes a cell holding
// light without a sample. Tombstones at a chain's end turn empty again.
TEST_F(HashGridTest, EvictionLeavesNoLightBehindAndContinuedLightMakesNoCell) {
  const uint32_t capacity = 1024;
  make(capacity);
  grid.cleared = false;
  run({capacity, 16, 1, 1, kInsert, 0, 1, 1, 0});  // key 0 in slot 0
  run({capacity, 16, 1, 1, kInsert, 1, 1, 1, 0});  // key 1 in slot 1
  run({capacity, 16, 1, 1, kInsert, 1, 1, 0, 0});  // more light for key 1's sample (count 0)
  run({capacity, 16, 1, 1, kEvict, 1, 1, 0, 0});   // key 1 goes, with its sums
  std::vector<uint32_t> keys;
  std::vector<gpu::HgAccum> accum;
  std::vector<uint32_t> samples;
  read(keys, accum, samples);
  EXPECT_EQ(keys[1], gpu::HG_EMPTY_KEY) << "the end of a chain needs no tombstone";
  EXPECT_EQ(accum[1].r, 0u);
  EXPECT_EQ(samples[1], 0u);
  // Continued light for a key that has no cell: dropped, nothing created.
  run({capacity, 16, 1, 1, kInsert, 2, 1, 0, 0});
  read(keys, accum, samples);
  EXPECT_EQ(keys[1], gpu::HG_EMPTY_KEY) << "count-0 light made a cell";
  EXPECT_EQ(gi::readHashGridTelemetry(grid, 0).failedInserts, 1u);
  // A new sample claims slot 1 and holds exactly its own light.
  run({capacity, 16, 1, 1, kInsert, 2, 1, 1, 0});
  read(keys, accum, samples);
  EXPECT_EQ(keys[1], keyOf(2));
  EXPECT_EQ(samples[1], 1u);
  EXPECT_EQ(accum[1].r, gpu::hgToFixed(1.0f));
  // Evicting slot 0 while slot 1 is full leaves a tombstone; once slot 1 is
  // gone too, tidying turns it empty.
  run({capacity, 16, 1, 1, kEvict, 0, 1, 0, 0});
  run({capacity, 16, 1, 1, kEvict, 2, 1, 0, 0});
  read(keys, accum, samples);
  EXPECT_EQ(keys[0], gpu::HG_TOMBSTONE_KEY);
  EXPECT_EQ(keys[1], gpu::HG_EMPTY_KEY);
  run({capacity, 16, 0, 1, kTidy, 0, 1, 0, 0});
  read(keys, accum, samples);
  EXPECT_EQ(keys[0], gpu::HG_EMPTY_KEY);
}
