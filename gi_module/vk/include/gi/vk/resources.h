// The module's buffers and images (memory from the device's arena) and the
// two barriers its passes use. Create functions leave the output empty when
// they fail; destroy functions accept empty resources.
#pragma once
#include "gi/vk/device.h"

namespace gi::vk {

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  Allocation memory;  // memory.mapped: the host pointer of a host-visible buffer
  VkDeviceSize size = 0;
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  Allocation memory;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{};
  VkImageView alsoView = VK_NULL_HANDLE;  // the texels as createImage's `alsoViewedAs` (none without it)
};

// On a simulated arena (MemoryArena::simulate) these create no object: they take the memory the
// object would need (vkGetDevice*MemoryRequirements) from the arena and leave the handles null.
Status createBuffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible, Buffer& out);
void destroyBuffer(Device& device, Buffer& buffer);
// A 2D colour image with one mip and a view of it. `transient`: its contents live within a frame.
// `alsoViewedAs`, a format of the same texel size: a second view (Image::alsoView) that reads and writes the
// same bits as that format (the image is then created mutable-format).
Status createImage(Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, Image& out,
                   bool transient = false, VkFormat alsoViewedAs = VK_FORMAT_UNDEFINED);
void destroyImage(Device& device, Image& image);

// Barriers (synchronization2): the structs, and one recording function that
// takes vkCmdPipelineBarrier2 from whichever table the caller uses (the
// module's, or the engine's loader).
VkImageMemoryBarrier2 imageBarrierInfo(VkImage image, VkImageLayout from, VkImageLayout to,
                                       VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                                       VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess,
                                       VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT, uint32_t baseMip = 0,
                                       uint32_t mipCount = VK_REMAINING_MIP_LEVELS);
VkMemoryBarrier2 memoryBarrierInfo(VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);
void recordBarrier(PFN_vkCmdPipelineBarrier2 cmdPipelineBarrier2, VkCommandBuffer cmd, const VkMemoryBarrier2* memory,
                   const VkImageMemoryBarrier2* image);

// Layout transition of a whole colour image.
void imageBarrier(const Device& device, VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess);
// Global memory barrier, for buffers and images that keep their layout.
void memoryBarrier(const Device& device, VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);
// Writes `bytes` (a multiple of 4) of `data` at the start of `buffer` (usage TRANSFER_DST) by commands in
// `cmd` (vkCmdUpdateBuffer, 64 KiB at a time): the data travels in the command buffer, so a write never
// touches memory that a frame in flight reads, and the frames recorded before see the old contents.
// Between beginBufferWrites and endBufferWrites: the first waits for every earlier command's reads, the
// second makes the writes visible to every later command.
void beginBufferWrites(const Device& device, VkCommandBuffer cmd);
void recordBufferWrite(const Device& device, VkCommandBuffer cmd, const Buffer& buffer, const void* data, size_t bytes,
                       VkDeviceSize offset = 0);  // bytes from `offset` (a multiple of 4, as is `bytes`)
// The same into a buffer of `bufferSize` bytes that is not the module's (an engine's).
void recordBufferWrite(const Device& device, VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize bufferSize,
                       const void* data, size_t bytes, VkDeviceSize offset = 0);
void endBufferWrites(const Device& device, VkCommandBuffer cmd);
// What a compute pass wrote, visible to the next compute pass (read and write).
void computeToComputeBarrier(const Device& device, VkCommandBuffer cmd);

}  // namespace gi::vk
