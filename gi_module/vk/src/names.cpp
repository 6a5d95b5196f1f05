#include "gi/vk/names.h"

// vulkan.hpp's to_string names every enum value of the headers it ships with; its dynamic dispatcher
// needs no prototypes (the module is built without them) and is never used here.
#define VULKAN_HPP_DISPATCH_LOADER_DYNAMIC 1
#include <vulkan/vulkan.hpp>

namespace gi::vk {

std::string formatName(VkFormat format) {
  return ::vk::to_string(::vk::Format(format)) + " (VkFormat " + std::to_string(int(format)) + ")";
}

std::string layoutName(VkImageLayout layout) {
  return ::vk::to_string(::vk::ImageLayout(layout)) + " (VkImageLayout " + std::to_string(int(layout)) + ")";
}

}  // namespace gi::vk
