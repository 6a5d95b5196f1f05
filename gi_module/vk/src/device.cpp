#include "gi/vk/device.h"

namespace gi::vk {

Status openDevice(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance, VkPhysicalDevice physicalDevice,
                  VkDevice device, Device& out) {
  out.instance = instance;
  out.physicalDevice = physicalDevice;
  out.device = device;
  if (!getInstanceProcAddr)
    return {VK_ERROR_INITIALIZATION_FAILED, "vkGetInstanceProcAddr (desc.getInstanceProcAddr is null)"};
  if (const char* missing = loadFunctions(getInstanceProcAddr, instance, device, out.fn))
    return {VK_ERROR_INITIALIZATION_FAILED, missing};
  out.fn.vkGetPhysicalDeviceProperties(physicalDevice, &out.properties);
  out.fn.vkGetPhysicalDeviceMemoryProperties(physicalDevice, &out.memoryProperties);
  return {};
}

void closeDevice(Device& d) { destroyArena(d); }

}  // namespace gi::vk
