// Vulkan enum values by name, for error messages a person reads: "R8G8Snorm (VkFormat 17)".
#pragma once
#include <vulkan/vulkan_core.h>

#include <string>

namespace gi::vk {

std::string formatName(VkFormat format);
std::string layoutName(VkImageLayout layout);

}  // namespace gi::vk
