#include "vulkan_host.h"

#include <gi/device.h>

#include <cstring>
#include <vector>

namespace example {
namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)) {
    static_cast<Host*>(user)->validationMessages++;
    std::fprintf(stderr, "[validation] %s\n", data->pMessage);
  }
  return VK_FALSE;
}

uint32_t memoryType(const Host& h, uint32_t bits, VkMemoryPropertyFlags flags) {
  for (uint32_t i = 0; i < h.memory.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (h.memory.memoryTypes[i].propertyFlags & flags) == flags) return i;
  std::fprintf(stderr, "no memory type with flags 0x%x\n", flags);
  std::exit(2);
}

// Vulkan 1.3 features: the module's (gi/device.h) and the raster's own.
struct FeatureChain {
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  FeatureChain() {
    f2.pNext = &f12;
    f12.pNext = &f13;
  }
  FeatureChain(const FeatureChain&) = delete;
};

}  // namespace

void createHost(bool validation, Host& h) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "gi example host";
  app.apiVersion = VK_API_VERSION_1_3;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  // Validation includes its synchronization checks: hazards between the host's commands and the module's,
  // across frames in flight.
  const VkValidationFeatureEnableEXT syncChecks = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &syncChecks;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = validation ? &features : nullptr;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = validation ? 1 : 0;
  info.ppEnabledLayerNames = layers;
  info.enabledExtensionCount = validation ? 2 : 0;
  info.ppEnabledExtensionNames = extensions;
  EXAMPLE_CHECK(vkCreateInstance(&info, nullptr, &h.instance));
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    m.pfnUserCallback = onMessage;
    m.pUserData = &h;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkCreateDebugUtilsMessengerEXT"));
    EXAMPLE_CHECK(create(h.instance, &m, nullptr, &h.messenger));
  }
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(h.instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(h.instance, &count, devices.data());
  for (VkPhysicalDevice d : devices) {
    FeatureChain supported;
    vkGetPhysicalDeviceFeatures2(d, &supported.f2);
    if (gi::firstMissingFeature(supported.f2, false) || !supported.f13.dynamicRendering) continue;
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, props.data());
    for (uint32_t i = 0; i < families && !h.physical; ++i)
      if ((props[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
          (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
        h.physical = d;
        h.queueFamily = i;
      }
    if (h.physical) break;
  }
  if (!h.physical) {
    std::fprintf(stderr, "no Vulkan 1.3 device with dynamic rendering and gi/device.h's features\n");
    std::exit(2);
  }
  vkGetPhysicalDeviceMemoryProperties(h.physical, &h.memory);
  FeatureChain enabled;
  enabled.f13.dynamicRendering = VK_TRUE;
  if (const char* missing = gi::enableRequiredFeatures(enabled.f2, false)) {
    std::fprintf(stderr, "the feature chain lacks the struct of %s\n", missing);
    std::exit(2);
  }
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = h.queueFamily;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo device{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device.pNext = &enabled.f2;
  device.queueCreateInfoCount = 1;
  device.pQueueCreateInfos = &queue;
  EXAMPLE_CHECK(vkCreateDevice(h.physical, &device, nullptr, &h.device));
  vkGetDeviceQueue(h.device, h.queueFamily, 0, &h.queue);
  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = h.queueFamily;
  EXAMPLE_CHECK(vkCreateCommandPool(h.device, &pool, nullptr, &h.pool));
}

void destroyHost(Host& h) {
  vkDestroyCommandPool(h.device, h.pool, nullptr);
  vkDestroyDevice(h.device, nullptr);
  if (h.messenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(h.instance, h.messenger, nullptr);
  }
  vkDestroyInstance(h.instance, nullptr);
}

Buffer createBuffer(const Host& h, VkDeviceSize size, VkBufferUsageFlags usage, const void* data) {
  Buffer b;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  EXAMPLE_CHECK(vkCreateBuffer(h.device, &info, nullptr, &b.buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(h.device, b.buffer, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      memoryType(h, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) alloc.pNext = &flags;
  EXAMPLE_CHECK(vkAllocateMemory(h.device, &alloc, nullptr, &b.memory));
  EXAMPLE_CHECK(vkBindBufferMemory(h.device, b.buffer, b.memory, 0));
  EXAMPLE_CHECK(vkMapMemory(h.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
  if (data)
    std::memcpy(b.mapped, data, size);
  else
    std::memset(b.mapped, 0, size);
  return b;
}

void destroyBuffer(const Host& h, Buffer& b) {
  vkDestroyBuffer(h.device, b.buffer, nullptr);
  vkFreeMemory(h.device, b.memory, nullptr);
  b = Buffer{};
}

Image createImage(const Host& h, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect) {
  Image img;
  img.format = format;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  EXAMPLE_CHECK(vkCreateImage(h.device, &info, nullptr, &img.image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(h.device, img.image, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = memoryType(h, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  EXAMPLE_CHECK(vkAllocateMemory(h.device, &alloc, nullptr, &img.memory));
  EXAMPLE_CHECK(vkBindImageMemory(h.device, img.image, img.memory, 0));
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = img.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {aspect, 0, 1, 0, 1};
  EXAMPLE_CHECK(vkCreateImageView(h.device, &view, nullptr, &img.view));
  return img;
}

void destroyImage(const Host& h, Image& img) {
  vkDestroyImageView(h.device, img.view, nullptr);
  vkDestroyImage(h.device, img.image, nullptr);
  vkFreeMemory(h.device, img.memory, nullptr);
  img = Image{};
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = srcStage;
  b.srcAccessMask = srcAccess;
  b.dstStageMask = dstStage;
  b.dstAccessMask = dstAccess;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, 0, 1, 0, 1};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = srcStage;
  b.srcAccessMask = srcAccess;
  b.dstStageMask = dstStage;
  b.dstAccessMask = dstAccess;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

VkShaderModule createShaderModule(const Host& h, const uint32_t* words, size_t bytes) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = bytes;
  info.pCode = words;
  VkShaderModule m;
  EXAMPLE_CHECK(vkCreateShaderModule(h.device, &info, nullptr, &m));
  return m;
}

void recordReadback(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, const Buffer& out, VkImageLayout layout) {
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, image, layout, out.buffer, 1, &region);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                VK_ACCESS_2_HOST_READ_BIT);
}

}  // namespace example
