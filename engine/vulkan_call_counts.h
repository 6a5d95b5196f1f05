// Counts the engine's own Vulkan calls that stall a frame or create something (issue 35's check that an
// animated frame waits on at most one fence and creates nothing): once started, volk's entry points for
// them go through counting wrappers. The GI module calls Vulkan through its own function table and is not
// counted here; its allocations are FrameStats::deviceAllocations.
#pragma once
#include <cstdint>

namespace engine {

struct VulkanCallCounts {
  uint64_t fenceWaits = 0;  // vkWaitForFences
  uint64_t idleWaits = 0;   // vkQueueWaitIdle, vkDeviceWaitIdle
  uint64_t creations = 0;   // vkAllocateMemory, vkCreateImage, vkCreateBuffer, vkCreate*Pipelines
};

// After the device's entry points are loaded (createContext; again after another createContext, which
// reloads them); idempotent. Not thread-safe with calls
// being made.
void startCountingVulkanCalls();
// Since startCountingVulkanCalls (all 0 before).
VulkanCallCounts vulkanCallCounts();
VulkanCallCounts operator-(const VulkanCallCounts& a, const VulkanCallCounts& b);

}  // namespace engine
