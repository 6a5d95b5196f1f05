// gi.h in an engine with its own loader: no prototypes, no volk, only the
// core header and its own function pointers. Compiling is the check.
#define VK_NO_PROTOTYPES
#include <vulkan/vulkan_core.h>

#include <gi/gi.h>

// The engine's own table would hold this; the module takes it from the desc.
PFN_vkGetInstanceProcAddr ownLoaderEntry = nullptr;

gi::ModuleDesc descFromOwnLoader() {
  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = ownLoaderEntry;
  return desc;
}
