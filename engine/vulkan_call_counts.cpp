#include "vulkan_call_counts.h"

#include <atomic>

#include "vk.h"

namespace engine {
namespace {

std::atomic<uint64_t> fenceWaits{0}, idleWaits{0}, creations{0};

// The entry points volk loaded, called by the wrappers.
PFN_vkWaitForFences realWaitForFences;
PFN_vkQueueWaitIdle realQueueWaitIdle;
PFN_vkDeviceWaitIdle realDeviceWaitIdle;
PFN_vkAllocateMemory realAllocateMemory;
PFN_vkCreateImage realCreateImage;
PFN_vkCreateBuffer realCreateBuffer;
PFN_vkCreateComputePipelines realCreateComputePipelines;
PFN_vkCreateGraphicsPipelines realCreateGraphicsPipelines;

VKAPI_ATTR VkResult VKAPI_CALL waitForFences(VkDevice d, uint32_t n, const VkFence* f, VkBool32 all, uint64_t timeout) {
  ++fenceWaits;
  return realWaitForFences(d, n, f, all, timeout);
}
VKAPI_ATTR VkResult VKAPI_CALL queueWaitIdle(VkQueue q) {
  ++idleWaits;
  return realQueueWaitIdle(q);
}
VKAPI_ATTR VkResult VKAPI_CALL deviceWaitIdle(VkDevice d) {
  ++idleWaits;
  return realDeviceWaitIdle(d);
}
VKAPI_ATTR VkResult VKAPI_CALL allocateMemory(VkDevice d, const VkMemoryAllocateInfo* i, const VkAllocationCallbacks* a,
                                              VkDeviceMemory* m) {
  ++creations;
  return realAllocateMemory(d, i, a, m);
}
VKAPI_ATTR VkResult VKAPI_CALL createImage(VkDevice d, const VkImageCreateInfo* i, const VkAllocationCallbacks* a,
                                           VkImage* image) {
  ++creations;
  return realCreateImage(d, i, a, image);
}
VKAPI_ATTR VkResult VKAPI_CALL createBuffer(VkDevice d, const VkBufferCreateInfo* i, const VkAllocationCallbacks* a,
                                            VkBuffer* buffer) {
  ++creations;
  return realCreateBuffer(d, i, a, buffer);
}
VKAPI_ATTR VkResult VKAPI_CALL createComputePipelines(VkDevice d, VkPipelineCache c, uint32_t n,
                                                      const VkComputePipelineCreateInfo* i,
                                                      const VkAllocationCallbacks* a, VkPipeline* p) {
  ++creations;
  return realCreateComputePipelines(d, c, n, i, a, p);
}
VKAPI_ATTR VkResult VKAPI_CALL createGraphicsPipelines(VkDevice d, VkPipelineCache c, uint32_t n,
                                                       const VkGraphicsPipelineCreateInfo* i,
                                                       const VkAllocationCallbacks* a, VkPipeline* p) {
  ++creations;
  return realCreateGraphicsPipelines(d, c, n, i, a, p);
}

// Routes volk's `entry` through `wrapper`, keeping the device's own function in `real`; a no-op when it
// already goes there. Each createContext reloads volk's entry points, so a second context is hooked anew.
template <typename Pfn>
void hook(Pfn& entry, Pfn& real, Pfn wrapper) {
  if (entry == wrapper) return;
  real = entry;
  entry = wrapper;
}

}  // namespace

void startCountingVulkanCalls() {
  hook(vkWaitForFences, realWaitForFences, &waitForFences);
  hook(vkQueueWaitIdle, realQueueWaitIdle, &queueWaitIdle);
  hook(vkDeviceWaitIdle, realDeviceWaitIdle, &deviceWaitIdle);
  hook(vkAllocateMemory, realAllocateMemory, &allocateMemory);
  hook(vkCreateImage, realCreateImage, &createImage);
  hook(vkCreateBuffer, realCreateBuffer, &createBuffer);
  hook(vkCreateComputePipelines, realCreateComputePipelines, &createComputePipelines);
  hook(vkCreateGraphicsPipelines, realCreateGraphicsPipelines, &createGraphicsPipelines);
}

VulkanCallCounts vulkanCallCounts() { return {fenceWaits.load(), idleWaits.load(), creations.load()}; }

VulkanCallCounts operator-(const VulkanCallCounts& a, const VulkanCallCounts& b) {
  return {a.fenceWaits - b.fenceWaits, a.idleWaits - b.idleWaits, a.creations - b.creations};
}

}  // namespace engine
