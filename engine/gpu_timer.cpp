#include "gpu_timer.h"

namespace engine {

namespace {
constexpr uint32_t kUntimed = UINT32_MAX;  // GpuTimer::open's mark for a pass past capacity
}

GpuTimer createGpuTimer(const Context& ctx, std::string& error, uint32_t maxPasses) {
  GpuTimer t;
  if (!error.empty()) return t;
  t.capacity = maxPasses;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * maxPasses;
  if (!VK_SUCCEEDED(error, "the GPU timer's queries", vkCreateQueryPool(ctx.device, &info, nullptr, &t.pool)))
    return GpuTimer{};
  t.nsPerTick = ctx.properties.limits.timestampPeriod;
  resetGpuTimer(ctx, t);
  return t;
}

void destroyGpuTimer(const Context& ctx, GpuTimer& t) {
  if (t.pool) vkDestroyQueryPool(ctx.device, t.pool, nullptr);
  t = GpuTimer{};
}

void resetGpuTimer(const Context& ctx, GpuTimer& t) {
  vkResetQueryPool(ctx.device, t.pool, 0, 2 * t.capacity);
  t.names.clear();
  t.open.clear();
  t.untimed = 0;
}

void beginPass(const Context& ctx, VkCommandBuffer cmd, GpuTimer& t, const char* name) {
  if (ctx.debugUtils) {
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    vkCmdBeginDebugUtilsLabelEXT(cmd, &label);
  }
  if (t.names.size() >= t.capacity) {  // readPassTimes reports it
    ++t.untimed;
    t.open.push_back(kUntimed);
    return;
  }
  uint32_t index = uint32_t(t.names.size());
  t.names.emplace_back(name);
  t.open.push_back(index);
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, t.pool, 2 * index);
  timestampFence(cmd);
}

void timestampFence(VkCommandBuffer cmd) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  b.srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  b.dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  b.dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void endPass(const Context& ctx, VkCommandBuffer cmd, GpuTimer& t) {
  uint32_t index = t.open.back();
  t.open.pop_back();
  if (index != kUntimed) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, t.pool, 2 * index + 1);
  if (ctx.debugUtils) vkCmdEndDebugUtilsLabelEXT(cmd);
}

std::vector<PassTime> readPassTimes(const Context& ctx, const GpuTimer& t, std::string& error) {
  std::vector<PassTime> out;
  if (!error.empty() || t.names.empty()) return out;
  if (t.untimed > 0) {
    error = "the GPU timer has room for " + std::to_string(t.capacity) + " passes a frame and this frame began " +
            std::to_string(t.capacity + t.untimed);
    return out;
  }
  std::vector<uint64_t> ticks(2 * t.names.size());
  if (!VK_SUCCEEDED(
          error, "reading the GPU timer",
          vkGetQueryPoolResults(ctx.device, t.pool, 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t),
                                ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT)))
    return out;
  for (size_t i = 0; i < t.names.size(); ++i)
    out.push_back({t.names[i], double(ticks[2 * i + 1] - ticks[2 * i]) * t.nsPerTick * 1e-6});
  return out;
}

}  // namespace engine
