// A second device on the context's GPU, created as the context's own (same
// features and extensions) with a queue of its own: what is submitted there
// never waits behind the context's frames. It calls Vulkan through a small
// table of its own, so the engine's global function pointers (volk's, loaded
// for the context's device) stay untouched. The demo compiles a method's
// programs on one before switching to it (sample_game/program_readiness.h).
#pragma once
#include <string>

#include "context.h"

namespace engine {

#define ENGINE_SECOND_DEVICE_FUNCTIONS(X) \
  X(vkDestroyDevice)                      \
  X(vkGetDeviceQueue)                     \
  X(vkCreateCommandPool)                  \
  X(vkDestroyCommandPool)                 \
  X(vkAllocateCommandBuffers)             \
  X(vkBeginCommandBuffer)                 \
  X(vkEndCommandBuffer)                   \
  X(vkQueueSubmit)                        \
  X(vkCreateFence)                        \
  X(vkDestroyFence)                       \
  X(vkWaitForFences)                      \
  X(vkDeviceWaitIdle)

struct SecondDevice {
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;
#define ENGINE_SECOND_DEVICE_MEMBER(name) PFN_##name name = nullptr;
  ENGINE_SECOND_DEVICE_FUNCTIONS(ENGINE_SECOND_DEVICE_MEMBER)
#undef ENGINE_SECOND_DEVICE_MEMBER
};

// False with one sentence in `error` when the device cannot be made.
bool createSecondDevice(const Context& ctx, SecondDevice& out, std::string& error);
void destroySecondDevice(SecondDevice& device);
// Begins a one-shot command buffer (null where it cannot); submitAndWaitSecond ends, submits and waits for it.
VkCommandBuffer beginSecond(const SecondDevice& device);
VkResult submitAndWaitSecond(const SecondDevice& device, VkCommandBuffer cmd);

}  // namespace engine
