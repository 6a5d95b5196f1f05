// The module's own Vulkan function table. The module is compiled with
// VK_NO_PROTOTYPES and calls Vulkan only through the table it loads from the
// engine's vkGetInstanceProcAddr, so it never reads or writes a process-wide
// function pointer (volk's or the loader's) and works beside any loader the
// engine uses. Every function the module calls is listed once, here.
#pragma once
#include <vulkan/vulkan_core.h>

namespace gi::vk {

// Instance-level functions (vkGetInstanceProcAddr with the engine's instance).
#define GI_VK_INSTANCE_FUNCTIONS(X)      \
  X(vkGetDeviceProcAddr)                 \
  X(vkGetPhysicalDeviceProperties)       \
  X(vkGetPhysicalDeviceMemoryProperties) \
  X(vkGetPhysicalDeviceProperties2)      \
  X(vkGetPhysicalDeviceFeatures2)        \
  X(vkGetPhysicalDeviceFormatProperties)

// Device-level functions (vkGetDeviceProcAddr with the engine's device); Vulkan 1.3 core.
#define GI_VK_DEVICE_FUNCTIONS(X)        \
  X(vkAllocateDescriptorSets)            \
  X(vkAllocateMemory)                    \
  X(vkBindBufferMemory)                  \
  X(vkBindImageMemory)                   \
  X(vkCmdBindDescriptorSets)             \
  X(vkCmdBindPipeline)                   \
  X(vkCmdCopyBuffer)                     \
  X(vkCmdCopyBufferToImage)              \
  X(vkCmdDispatch)                       \
  X(vkCmdFillBuffer)                     \
  X(vkCmdPipelineBarrier2)               \
  X(vkCmdSetEvent2)                      \
  X(vkCmdPushConstants)                  \
  X(vkCmdUpdateBuffer)                   \
  X(vkCmdResetQueryPool)                 \
  X(vkCmdWriteTimestamp2)                \
  X(vkCreateBuffer)                      \
  X(vkCreateBufferView)                  \
  X(vkCreateComputePipelines)            \
  X(vkCreateDescriptorPool)              \
  X(vkCreateDescriptorSetLayout)         \
  X(vkCreateEvent)                       \
  X(vkCreateImage)                       \
  X(vkCreateImageView)                   \
  X(vkCreatePipelineLayout)              \
  X(vkCreateQueryPool)                   \
  X(vkCreateSampler)                     \
  X(vkCreateShaderModule)                \
  X(vkDestroyBuffer)                     \
  X(vkDestroyBufferView)                 \
  X(vkDestroyDescriptorPool)             \
  X(vkDestroyDescriptorSetLayout)        \
  X(vkDestroyEvent)                      \
  X(vkDestroyImage)                      \
  X(vkDestroyImageView)                  \
  X(vkDestroyPipeline)                   \
  X(vkDestroyPipelineLayout)             \
  X(vkDestroyQueryPool)                  \
  X(vkDestroySampler)                    \
  X(vkDestroyShaderModule)               \
  X(vkFreeMemory)                        \
  X(vkGetBufferDeviceAddress)            \
  X(vkGetBufferMemoryRequirements)       \
  X(vkGetDeviceBufferMemoryRequirements) \
  X(vkGetDeviceImageMemoryRequirements)  \
  X(vkGetEventStatus)                    \
  X(vkGetImageMemoryRequirements)        \
  X(vkGetQueryPoolResults)               \
  X(vkMapMemory)                         \
  X(vkResetEvent)                        \
  X(vkUpdateDescriptorSets)

// Optional: present only when the instance enabled VK_EXT_debug_utils, or
// the device VK_KHR_acceleration_structure (scenes traced with ray queries).
#define GI_VK_OPTIONAL_DEVICE_FUNCTIONS(X)   \
  X(vkCmdBeginDebugUtilsLabelEXT)            \
  X(vkCmdEndDebugUtilsLabelEXT)              \
  X(vkCmdBuildAccelerationStructuresKHR)     \
  X(vkCreateAccelerationStructureKHR)        \
  X(vkDestroyAccelerationStructureKHR)       \
  X(vkGetAccelerationStructureBuildSizesKHR) \
  X(vkGetAccelerationStructureDeviceAddressKHR)

struct Functions {
#define GI_VK_MEMBER(name) PFN_##name name = nullptr;
  GI_VK_INSTANCE_FUNCTIONS(GI_VK_MEMBER)
  GI_VK_DEVICE_FUNCTIONS(GI_VK_MEMBER)
  GI_VK_OPTIONAL_DEVICE_FUNCTIONS(GI_VK_MEMBER)
#undef GI_VK_MEMBER
};

// Loads the table. Returns the name of the first required function the
// loader did not return, or nullptr when all were found.
const char* loadFunctions(PFN_vkGetInstanceProcAddr getInstanceProcAddr, VkInstance instance, VkDevice device,
                          Functions& out);

}  // namespace gi::vk
