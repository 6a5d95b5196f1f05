// The device the module records for: the engine's handles, the module's own
// function table (gi/vk/functions.h), the engine's host allocation callbacks
// and pipeline cache, and the module's device-memory arena.
#pragma once
#include "gi/vk/memory_arena.h"
#include "gi/vk/status.h"
#include "gi/vk/functions.h"

namespace gi::vk {

struct Device {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  Functions fn;
  VkPhysicalDeviceProperties properties{};
  VkPhysicalDeviceMemoryProperties memoryProperties{};
  const VkAllocationCallbacks* allocator = nullptr;  // the engine's, for every vkCreate*/vkAllocate* (may be null)
  VkPipelineCache pipelineCache = VK_NULL_HANDLE;    // the engine's (may be null)
  MemoryArena memory;                                // every buffer and image the module owns lives here
  bool deviceAddressMemory = false;  // blocks allocated with DEVICE_ADDRESS (acceleration-structure inputs)
};

// Loads the function table and the device's properties. A loader that lacks a
// required function gives VK_ERROR_INITIALIZATION_FAILED with `call` naming it.
Status openDevice(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance, VkPhysicalDevice physicalDevice,
                  VkDevice device, Device& out);
// Frees the arena's blocks (every resource must have been destroyed).
void closeDevice(Device& device);

}  // namespace gi::vk
