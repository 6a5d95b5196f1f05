// The example hosts' Vulkan (examples/foreign_engine, examples/standalone_host):
// the system loader with prototypes, their own instance (with the validation
// layer on request, counting its messages), device, queue, command pool, and
// plain buffers and images with their own memory. Nothing from the GI
// repository but the module's public headers.
#pragma once
#include <vulkan/vulkan.h>  // before gi.h: the host's own Vulkan header, prototypes and all

#include <gi/gi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace example {

#define EXAMPLE_CHECK(call)                                                   \
  do {                                                                        \
    if (VkResult r_ = (call); r_ != VK_SUCCESS) {                             \
      std::fprintf(stderr, "%s failed with %s\n", #call, gi::resultName(r_)); \
      std::exit(2);                                                           \
    }                                                                         \
  } while (0)

struct Host {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory{};
  uint32_t validationMessages = 0;
};

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;  // host-visible, coherent
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
};

// A graphics + compute queue on the first device with the GI module's
// features (gi/device.h, compute traversal) and dynamic rendering.
void createHost(bool validation, Host& h);
void destroyHost(Host& h);

Buffer createBuffer(const Host& h, VkDeviceSize size, VkBufferUsageFlags usage, const void* data = nullptr);
void destroyBuffer(const Host& h, Buffer& b);
Image createImage(const Host& h, VkFormat format, VkExtent2D extent, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect);
VkShaderModule createShaderModule(const Host& h, const uint32_t* words, size_t bytes);
void destroyImage(const Host& h, Image& img);

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess);
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

// Copies a module output (in `layout`: gi::ModuleDesc::outputLayout; GENERAL,
// written by compute shaders) into a host-visible buffer, readable on the host
// once `cmd` completes.
void recordReadback(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, const Buffer& out,
                    VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);

// One command buffer, recorded by `record`, submitted and waited for.
template <typename F>
void submitOnce(const Host& h, F&& record) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = h.pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd;
  EXAMPLE_CHECK(vkAllocateCommandBuffers(h.device, &alloc, &cmd));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  EXAMPLE_CHECK(vkBeginCommandBuffer(cmd, &begin));
  record(cmd);
  EXAMPLE_CHECK(vkEndCommandBuffer(cmd));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  EXAMPLE_CHECK(vkQueueSubmit(h.queue, 1, &submit, VK_NULL_HANDLE));
  EXAMPLE_CHECK(vkQueueWaitIdle(h.queue));
  vkFreeCommandBuffers(h.device, h.pool, 1, &cmd);
}

}  // namespace example
