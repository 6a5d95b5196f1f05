// How the module's internal Vulkan calls fail: a Status (the VkResult and
// the call) is returned up to the public API, which turns it into a gi::Error.
// Nothing in the module aborts the host process.
#pragma once
#include <vulkan/vulkan_core.h>

namespace gi::vk {

// A failed Vulkan call: its result and the call, for gi::Error's message.
struct Status {
  VkResult result = VK_SUCCESS;
  const char* call = nullptr;
  explicit operator bool() const { return result != VK_SUCCESS; }
};

// Returns a Status from the enclosing function when a Vulkan call fails.
#define GI_VK(call)                                                                                                  \
  do {                                                                                                               \
    if (VkResult gi_vk_result_ = (call); gi_vk_result_ != VK_SUCCESS) return ::gi::vk::Status{gi_vk_result_, #call}; \
  } while (0)
// Passes on the Status of a module function that failed.
#define GI_TRY(expr)                                                     \
  do {                                                                   \
    if (::gi::vk::Status gi_try_status_ = (expr)) return gi_try_status_; \
  } while (0)

}  // namespace gi::vk
