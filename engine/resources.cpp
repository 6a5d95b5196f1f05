#include "resources.h"

#include "gi/vk/names.h"
#include "gi/vk/resources.h"

#include <cstring>
#include <vector>

namespace engine {

bool findMemoryType(const Context& ctx, uint32_t typeBits, VkMemoryPropertyFlags flags, uint32_t& type,
                    std::string& error) {
  for (uint32_t i = 0; i < ctx.memoryProperties.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (ctx.memoryProperties.memoryTypes[i].propertyFlags & flags) == flags) {
      type = i;
      return true;
    }
  char text[160];
  std::snprintf(text, sizeof text, "no Vulkan memory type has the flags 0x%x (allowed types 0x%x)", flags, typeBits);
  error = text;
  return false;
}

namespace {

// Memory for `req` (device-addressable when asked), bound by the caller.
bool allocateMemory(const Context& ctx, const VkMemoryRequirements& req, VkMemoryPropertyFlags flags,
                    bool deviceAddress, const char* what, VkDeviceMemory& memory, std::string& error) {
  VkMemoryAllocateFlagsInfo addressFlags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  addressFlags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  if (deviceAddress) alloc.pNext = &addressFlags;
  alloc.allocationSize = req.size;
  return findMemoryType(ctx, req.memoryTypeBits, flags, alloc.memoryTypeIndex, error) &&
         VK_SUCCEEDED(error, what, vkAllocateMemory(ctx.device, &alloc, nullptr, &memory));
}

std::string bufferWhat(VkDeviceSize size) { return "a buffer of " + std::to_string(size) + " bytes"; }

}  // namespace

Buffer createBuffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryKind kind,
                    std::string& error) {
  Buffer b;
  if (!error.empty()) return b;
  b.size = size;
  const std::string what = bufferWhat(size);
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size > 0 ? size : 16;  // zero-sized buffers are invalid; callers may have empty tables
  info.usage = usage;
  const bool hostVisible = kind == MemoryKind::HostVisible;
  const bool addressed = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
  VkMemoryRequirements req{};
  if (VK_SUCCEEDED(error, what.c_str(), vkCreateBuffer(ctx.device, &info, nullptr, &b.buffer)))
    vkGetBufferMemoryRequirements(ctx.device, b.buffer, &req);
  const bool made =
      error.empty() &&
      allocateMemory(ctx, req,
                     hostVisible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                 : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                     addressed, what.c_str(), b.memory, error) &&
      VK_SUCCEEDED(error, what.c_str(), vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0)) &&
      (!hostVisible ||
       VK_SUCCEEDED(error, what.c_str(), vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped)));
  if (!made) {
    destroyBuffer(ctx, b);
    return b;
  }
  if (addressed) {
    VkBufferDeviceAddressInfo addr{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    addr.buffer = b.buffer;
    b.address = vkGetBufferDeviceAddress(ctx.device, &addr);
  }
  return b;
}

void destroyBuffer(const Context& ctx, Buffer& b) {
  if (b.buffer) vkDestroyBuffer(ctx.device, b.buffer, nullptr);
  if (b.memory) vkFreeMemory(ctx.device, b.memory, nullptr);
  b = Buffer{};
}

Buffer createBufferWithData(const Context& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
                            std::string& error) {
  Buffer b = createBuffer(ctx, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryKind::DeviceLocal, error);
  if (size == 0 || !error.empty()) return b;
  Buffer staging = createBuffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryKind::HostVisible, error);
  if (staging.mapped) std::memcpy(staging.mapped, data, size);
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, size};
        vkCmdCopyBuffer(cmd, staging.buffer, b.buffer, 1, &region);
      },
      error);
  destroyBuffer(ctx, staging);
  if (!error.empty()) destroyBuffer(ctx, b);
  return b;
}

bool isDepthFormat(VkFormat format) {
  return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D24_UNORM_S8_UINT || format == VK_FORMAT_D16_UNORM;
}

Image createImage(const Context& ctx, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, std::string& error,
                  uint32_t mipLevels) {
  Image img;
  if (!error.empty()) return img;
  img.format = format;
  img.extent = extent;
  img.mipLevels = mipLevels;
  const std::string what = "a " + std::to_string(extent.width) + "x" + std::to_string(extent.height) + " image of " +
                           gi::vk::formatName(format);
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = mipLevels;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkMemoryRequirements req{};
  if (VK_SUCCEEDED(error, what.c_str(), vkCreateImage(ctx.device, &info, nullptr, &img.image)))
    vkGetImageMemoryRequirements(ctx.device, img.image, &req);
  img.allocationSize = req.size;
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = img.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {
      VkImageAspectFlags(isDepthFormat(format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT), 0, mipLevels,
      0, 1};
  const bool made =
      error.empty() &&
      allocateMemory(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, false, what.c_str(), img.memory, error) &&
      VK_SUCCEEDED(error, what.c_str(), vkBindImageMemory(ctx.device, img.image, img.memory, 0)) &&
      VK_SUCCEEDED(error, what.c_str(), vkCreateImageView(ctx.device, &view, nullptr, &img.view));
  if (!made) destroyImage(ctx, img);
  return img;
}

void destroyImage(const Context& ctx, Image& img) {
  if (img.view) vkDestroyImageView(ctx.device, img.view, nullptr);
  if (img.image) vkDestroyImage(ctx.device, img.image, nullptr);
  if (img.memory) vkFreeMemory(ctx.device, img.memory, nullptr);
  img = Image{};
}

namespace {
// One mip of a colour image: the general barrier restricted to that level.
void mipBarrier(VkCommandBuffer cmd, VkImage image, uint32_t mip, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                VkAccessFlags2 dstAccess) {
  imageBarrier(cmd, image, from, to, srcStage, srcAccess, dstStage, dstAccess, VK_IMAGE_ASPECT_COLOR_BIT, mip, 1);
}
}  // namespace

bool uploadImageWithMips(const Context& ctx, Image& img, const void* texels, size_t bytes, std::string& error) {
  Buffer staging = createBuffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryKind::HostVisible, error);
  if (staging.mapped) std::memcpy(staging.mapped, texels, bytes);
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {img.extent.width, img.extent.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.buffer, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        int32_t w = int32_t(img.extent.width), h = int32_t(img.extent.height);
        for (uint32_t mip = 1; mip < img.mipLevels; ++mip) {
          mipBarrier(cmd, img.image, mip - 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
          VkImageBlit blit{};
          blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, mip - 1, 0, 1};
          blit.srcOffsets[1] = {w, h, 1};
          w = w > 1 ? w / 2 : 1;
          h = h > 1 ? h / 2 : 1;
          blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, mip, 0, 1};
          blit.dstOffsets[1] = {w, h, 1};
          vkCmdBlitImage(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img.image,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        }
        // Every mip but the last is in TRANSFER_SRC now; the last is in TRANSFER_DST.
        for (uint32_t mip = 0; mip < img.mipLevels; ++mip) {
          VkImageLayout from =
              mip + 1 < img.mipLevels ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
          mipBarrier(cmd, img.image, mip, from, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                     VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_READ_BIT);
        }
      },
      error);
  destroyBuffer(ctx, staging);
  return error.empty();
}

bool uploadImage(const Context& ctx, Image& img, const void* texels, size_t bytes, VkImageLayout finalLayout,
                 std::string& error) {
  Buffer staging = createBuffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryKind::HostVisible, error);
  if (staging.mapped) std::memcpy(staging.mapped, texels, bytes);
  const VkImageAspectFlags aspect = isDepthFormat(img.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     aspect);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {aspect, 0, 0, 1};
        copy.imageExtent = {img.extent.width, img.extent.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.buffer, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, finalLayout,
                     VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     aspect);
      },
      error);
  destroyBuffer(ctx, staging);
  return error.empty();
}

bool makeStorageImagesGeneral(const Context& ctx, std::span<const Image> images, std::string& error) {
  return submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        for (const Image& img : images)
          imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, 0,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
      },
      error);
}

std::vector<std::byte> readbackImage(const Context& ctx, const Image& img, VkImageLayout layout, size_t texelBytes,
                                     std::string& error) {
  size_t bytes = size_t(img.extent.width) * img.extent.height * texelBytes;
  Buffer staging = createBuffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryKind::HostVisible, error);
  VkImageAspectFlags aspect = isDepthFormat(img.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        imageBarrier(cmd, img.image, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                     aspect);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {aspect, 0, 0, 1};
        copy.imageExtent = {img.extent.width, img.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer, 1, &copy);
        imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, aspect);
      },
      error);
  std::vector<std::byte> out;
  if (error.empty())
    out.assign(static_cast<const std::byte*>(staging.mapped), static_cast<const std::byte*>(staging.mapped) + bytes);
  destroyBuffer(ctx, staging);
  return out;
}

// The module's Vulkan layer fills the barrier structs; the engine records them through volk.
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess, VkImageAspectFlags aspect, uint32_t baseMip, uint32_t mipCount) {
  VkImageMemoryBarrier2 b =
      gi::vk::imageBarrierInfo(image, from, to, srcStage, srcAccess, dstStage, dstAccess, aspect, baseMip, mipCount);
  gi::vk::recordBarrier(vkCmdPipelineBarrier2, cmd, nullptr, &b);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 b = gi::vk::memoryBarrierInfo(srcStage, srcAccess, dstStage, dstAccess);
  gi::vk::recordBarrier(vkCmdPipelineBarrier2, cmd, &b, nullptr);
}

}  // namespace engine
