#include "gi/vk/resources.h"

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace gi::vk {

Status createBuffer(Device& d, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible, Buffer& out) {
  Buffer b;
  b.size = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size > 0 ? size : 16;  // a zero-sized buffer is invalid
  info.usage = usage;
  auto build = [&]() -> Status {
    if (d.memory.simulate) {
      const VkDeviceBufferMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_BUFFER_MEMORY_REQUIREMENTS, nullptr, &info};
      VkMemoryRequirements2 req{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
      d.fn.vkGetDeviceBufferMemoryRequirements(d.device, &query, &req);
      return allocate(d, req.memoryRequirements, hostVisible, true, false, b.memory);
    }
    GI_VK(d.fn.vkCreateBuffer(d.device, &info, d.allocator, &b.buffer));
    VkMemoryRequirements req;
    d.fn.vkGetBufferMemoryRequirements(d.device, b.buffer, &req);
    GI_TRY(allocate(d, req, hostVisible, true, false, b.memory));
    GI_VK(d.fn.vkBindBufferMemory(d.device, b.buffer, b.memory.memory, b.memory.offset));
    return {};
  };
  if (Status s = build()) {
    destroyBuffer(d, b);
    return s;
  }
  out = b;
  return {};
}

void destroyBuffer(Device& d, Buffer& b) {
  if (b.buffer) d.fn.vkDestroyBuffer(d.device, b.buffer, d.allocator);
  release(d, b.memory);
  b = Buffer{};
}

Status createImage(Device& d, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, Image& out, bool transient,
                   VkFormat alsoViewedAs) {
  Image img;
  img.format = format;
  img.extent = extent;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  // A second view's format is named in a format list, not left open: a driver that compresses images (DCC)
  // may keep compressing one whose formats it can list, where a bare MUTABLE_FORMAT image loses it.
  const VkFormat viewFormats[] = {format, alsoViewedAs};
  const VkImageFormatListCreateInfo formatList{VK_STRUCTURE_TYPE_IMAGE_FORMAT_LIST_CREATE_INFO, nullptr,
                                               uint32_t(std::size(viewFormats)), viewFormats};
  if (alsoViewedAs != VK_FORMAT_UNDEFINED) {
    info.flags = VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT;
    info.pNext = &formatList;
  }
  auto build = [&]() -> Status {
    if (d.memory.simulate) {
      const VkDeviceImageMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_IMAGE_MEMORY_REQUIREMENTS, nullptr, &info,
                                                  VkImageAspectFlagBits(0)};
      VkMemoryRequirements2 req{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
      d.fn.vkGetDeviceImageMemoryRequirements(d.device, &query, &req);
      return allocate(d, req.memoryRequirements, false, false, transient, img.memory);
    }
    GI_VK(d.fn.vkCreateImage(d.device, &info, d.allocator, &img.image));
    VkMemoryRequirements req;
    d.fn.vkGetImageMemoryRequirements(d.device, img.image, &req);
    GI_TRY(allocate(d, req, false, false, transient, img.memory));
    GI_VK(d.fn.vkBindImageMemory(d.device, img.image, img.memory.memory, img.memory.offset));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    GI_VK(d.fn.vkCreateImageView(d.device, &view, d.allocator, &img.view));
    if (alsoViewedAs != VK_FORMAT_UNDEFINED) {
      view.format = alsoViewedAs;
      GI_VK(d.fn.vkCreateImageView(d.device, &view, d.allocator, &img.alsoView));
    }
    return {};
  };
  if (Status s = build()) {
    destroyImage(d, img);
    return s;
  }
  out = img;
  return {};
}

void destroyImage(Device& d, Image& img) {
  if (img.view) d.fn.vkDestroyImageView(d.device, img.view, d.allocator);
  if (img.alsoView) d.fn.vkDestroyImageView(d.device, img.alsoView, d.allocator);
  if (img.image) d.fn.vkDestroyImage(d.device, img.image, d.allocator);
  release(d, img.memory);
  img = Image{};
}

VkImageMemoryBarrier2 imageBarrierInfo(VkImage image, VkImageLayout from, VkImageLayout to,
                                       VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                                       VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess,
                                       VkImageAspectFlags aspect, uint32_t baseMip, uint32_t mipCount) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = srcStage;
  b.srcAccessMask = srcAccess;
  b.dstStageMask = dstStage;
  b.dstAccessMask = dstAccess;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, baseMip, mipCount, 0, 1};
  return b;
}

VkMemoryBarrier2 memoryBarrierInfo(VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = srcStage;
  b.srcAccessMask = srcAccess;
  b.dstStageMask = dstStage;
  b.dstAccessMask = dstAccess;
  return b;
}

void recordBarrier(PFN_vkCmdPipelineBarrier2 cmdPipelineBarrier2, VkCommandBuffer cmd, const VkMemoryBarrier2* memory,
                   const VkImageMemoryBarrier2* image) {
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = memory ? 1 : 0;
  dep.pMemoryBarriers = memory;
  dep.imageMemoryBarrierCount = image ? 1 : 0;
  dep.pImageMemoryBarriers = image;
  cmdPipelineBarrier2(cmd, &dep);
}

void imageBarrier(const Device& d, VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess) {
  VkImageMemoryBarrier2 b = imageBarrierInfo(image, from, to, srcStage, srcAccess, dstStage, dstAccess);
  recordBarrier(d.fn.vkCmdPipelineBarrier2, cmd, nullptr, &b);
}

void memoryBarrier(const Device& d, VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 b = memoryBarrierInfo(srcStage, srcAccess, dstStage, dstAccess);
  recordBarrier(d.fn.vkCmdPipelineBarrier2, cmd, &b, nullptr);
}

void beginBufferWrites(const Device& d, VkCommandBuffer cmd) {
  // Earlier reads (shaders, acceleration-structure builds) before the writes: an execution dependency.
  memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

void recordBufferWrite(const Device& d, VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize bufferSize, const void* data,
                       size_t bytes, VkDeviceSize offset) {
  constexpr size_t kMaxUpdate = 65536;  // vkCmdUpdateBuffer's limit per call
  for (size_t at = 0; at < bytes && offset + at < bufferSize; at += kMaxUpdate) {
    const size_t n = std::min({kMaxUpdate, bytes - at, size_t(bufferSize - offset) - at});
    d.fn.vkCmdUpdateBuffer(cmd, buffer, offset + at, n, static_cast<const std::byte*>(data) + at);
  }
}

void recordBufferWrite(const Device& d, VkCommandBuffer cmd, const Buffer& buffer, const void* data, size_t bytes,
                       VkDeviceSize offset) {
  recordBufferWrite(d, cmd, buffer.buffer, buffer.size, data, bytes, offset);
}

void endBufferWrites(const Device& d, VkCommandBuffer cmd) {
  memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
}

void computeToComputeBarrier(const Device& d, VkCommandBuffer cmd) {
  memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

}  // namespace gi::vk
