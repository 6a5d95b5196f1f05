// FrameStats from a frame slot: its timestamps (ready once the frame has
// completed), the counters it copied back, and the hash map's telemetry.
#include <algorithm>
#include <cstring>

#include "module.h"

namespace gi {
namespace {

// The median pixel's history length from the temporal pass's histogram (0 where it did not run).
uint32_t medianHistoryFrames(const gpu::GiCounters& c) {
  uint64_t total = 0;
  for (uint32_t count : c.historyFrames) total += count;
  uint64_t below = 0;
  for (uint32_t bin = 0; bin < gpu::GI_HISTORY_BINS; ++bin) {
    below += c.historyFrames[bin];
    if (total > 0 && 2 * below >= total) return bin;
  }
  return 0;
}

}  // namespace

bool readFrameStats(Module& m, uint32_t slot, FrameStats& st) {
  const FrameSlot& fs = m.slots[slot];
  if (!fs.recorded) return false;
  const uint32_t n = std::min(uint32_t(fs.passes.size()), kMaxPasses);
  std::vector<uint64_t> ticks(2 * n);
  if (m.timestamps && n > 0) {
    // VK_NOT_READY while the frame is in flight (without timestamps the caller's fence is trusted).
    VkResult r = m.gpu.fn.vkGetQueryPoolResults(m.gpu.device, m.timestamps, slot * kMaxPasses * 2, 2 * n,
                                                ticks.size() * 8, ticks.data(), 8, VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) return false;
  }
  st = FrameStats{};
  st.frameIndex = fs.frameIndex;
  for (uint32_t i = 0; i < fs.passes.size(); ++i) {
    double ms = 0.0;
    if (m.timestamps && i < n)
      ms = double(ticks[2 * i + 1] - ticks[2 * i]) * m.gpu.properties.limits.timestampPeriod * 1e-6;
    const PassInfo& info = passInfo(fs.passes[i]);
    st.passes.push_back({info.name, ms, info.tracesRays});
    st.totalMs += ms;
  }
  const gpu::GiCounters c = slotCounters(m, slot);
  st.raysTraced = c.raysTraced;
  st.sanitized = c.sanitized;
  st.boundsViolations = c.boundsViolations;
  st.skyPicks = {c.skyPicksTested, c.skyPicksVisible, fs.skyVisibility};
  st.accumulatedFrames = std::max(fs.history, medianHistoryFrames(c));
  st.samplesPerPixel = fs.spp;
  const uint32_t pixels = m.width * m.height;
  if (c.tracedSamples > 0 && pixels > 0) st.samplesPerPixel = (c.tracedSamples + pixels / 2) / pixels;  // AAF: mean
  st.memoryBytes = m.gpu.memory.held;
  st.memoryUsedBytes = m.gpu.memory.used;
  st.memoryTransientBytes = m.sized.frameBytes;
  st.deviceAllocations = m.gpu.memory.allocations;
  if (usesHashGrid(fs.method) && m.hash.capacity) {
    gpu::HgTelemetry t = readHashGridTelemetry(m.hash, slot);
    st.boundsViolations += t.outOfBounds;
    st.hash.capacity = m.hash.capacity;
    st.hash.secondaryWidth = fs.hashSecondaryWidth;
    st.hash.occupied = t.occupied;
    st.hash.inserts = t.inserts;
    st.hash.failedInserts = t.failedInserts;
    st.hash.claimed = t.claimed;
    st.hash.meanProbe = t.inserts ? float(t.probeSum) / float(t.inserts) : 0.0f;
    st.hash.maxProbe = t.probeMax;
    st.hash.evicted = t.evicted;
    st.hash.overflows = t.overflows;
    st.hash.staleResets = t.staleResets;
    st.hash.transported = double(t.transported) / HG_FIXED_POINT_SCALE * m.desc.scene.typicalRadiance;
    st.hash.meanContinuationDepth = t.continued ? float(t.depthSum) / float(t.continued) : 0.0f;
    st.hash.reads = t.reads;
    st.hash.readMisses = t.readMisses;
  }
  return true;
}

FrameStats stats(Module* m) {
  // Newest recorded slot first; a slot whose frame has not completed is skipped.
  for (uint32_t back = 1; back <= m->desc.framesInFlight && back <= m->recordedFrames; ++back) {
    uint32_t slot = uint32_t((m->recordedFrames - back) % m->desc.framesInFlight);
    FrameStats st;
    if (readFrameStats(*m, slot, st)) {
      m->lastStats = st;
      break;
    }
  }
  return m->lastStats;
}

bool frameStats(Module* m, uint32_t frameIndex, FrameStats& out) {
  for (uint32_t slot = 0; slot < m->desc.framesInFlight; ++slot)
    if (m->slots[slot].recorded && m->slots[slot].frameIndex == frameIndex) return readFrameStats(*m, slot, out);
  return false;
}

}  // namespace gi
