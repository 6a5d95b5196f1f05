// The one include for Vulkan in this project: volk loads every entry point, so
// nothing links libvulkan directly. VK_CHECK names the call, file, line and
// result, then aborts: a failed Vulkan call inside the engine is a bug or a
// lost device, never a user error (user errors are reported before any call).
#pragma once
#include <volk.h>

#include <cstdio>
#include <cstdlib>

namespace engine {
const char* vkResultName(VkResult result);
}

#define VK_CHECK(call)                                                              \
  do {                                                                              \
    VkResult vk_check_result_ = (call);                                             \
    if (vk_check_result_ != VK_SUCCESS) {                                           \
      std::fprintf(stderr, "%s:%d: %s failed with %s\n", __FILE__, __LINE__, #call, \
                   engine::vkResultName(vk_check_result_));                         \
      std::abort();                                                                 \
    }                                                                               \
  } while (0)
