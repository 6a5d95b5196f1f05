#include "gi/vk/functions.h"

namespace gi::vk {

const char* loadFunctions(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance, VkDevice device,
                          Functions& f) {
  f = Functions{};
#define GI_VK_LOAD_INSTANCE(name)                                              \
  f.name = reinterpret_cast<PFN_##name>(getInstanceProcAddr(instance, #name)); \
  if (!f.name) return #name;
  GI_VK_INSTANCE_FUNCTIONS(GI_VK_LOAD_INSTANCE)
#undef GI_VK_LOAD_INSTANCE
#define GI_VK_LOAD_DEVICE(name)                                                \
  f.name = reinterpret_cast<PFN_##name>(f.vkGetDeviceProcAddr(device, #name)); \
  if (!f.name) return #name;
  GI_VK_DEVICE_FUNCTIONS(GI_VK_LOAD_DEVICE)
#undef GI_VK_LOAD_DEVICE
#define GI_VK_LOAD_OPTIONAL(name) f.name = reinterpret_cast<PFN_##name>(f.vkGetDeviceProcAddr(device, #name));
  GI_VK_OPTIONAL_DEVICE_FUNCTIONS(GI_VK_LOAD_OPTIONAL)
#undef GI_VK_LOAD_OPTIONAL
  return nullptr;
}

}  // namespace gi::vk
