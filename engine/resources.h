// GPU buffers and images as plain structs with create/destroy functions.
// One VkDeviceMemory per resource: scenes here hold a few hundred resources at
// most, well under maxMemoryAllocationCount.
#pragma once
#include "context.h"

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace engine {

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;       // non-null for host-visible buffers
  VkDeviceAddress address = 0;  // non-zero when created with SHADER_DEVICE_ADDRESS usage
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{};
  uint32_t mipLevels = 1;
  VkDeviceSize allocationSize = 0;  // device memory behind the image, bytes
};

enum class MemoryKind { DeviceLocal, HostVisible };

// Each create/upload/readback below follows vk.h's error style: on failure (or with `error` already
// set) it leaves nothing behind, returns an empty resource or false, and `error` names what failed.
Buffer createBuffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, MemoryKind kind,
                    std::string& error);
void destroyBuffer(const Context& ctx, Buffer& buffer);

// Device-local buffer filled through a staging copy (waits for completion).
Buffer createBufferWithData(const Context& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
                            std::string& error);
template <typename T>
Buffer createBufferFrom(const Context& ctx, std::span<const T> data, VkBufferUsageFlags usage, std::string& error) {
  return createBufferWithData(ctx, data.data(), data.size_bytes(), usage, error);
}

Image createImage(const Context& ctx, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, std::string& error,
                  uint32_t mipLevels = 1);
void destroyImage(const Context& ctx, Image& image);

// Uploads tightly packed texels into mip 0, builds the other mips with blits and
// leaves the image in SHADER_READ_ONLY_OPTIMAL.
bool uploadImageWithMips(const Context& ctx, Image& image, const void* texels, size_t bytes, std::string& error);

// Uploads tightly packed texels into mip 0 of a single-mip image and leaves it in `finalLayout`; waits.
bool uploadImage(const Context& ctx, Image& image, const void* texels, size_t bytes, VkImageLayout finalLayout,
                 std::string& error);

// Moves new storage images from UNDEFINED to GENERAL for compute passes to write; waits.
bool makeStorageImagesGeneral(const Context& ctx, std::span<const Image> images, std::string& error);

// Copies an image (in `layout`) to host memory, tightly packed; waits. Empty on failure.
std::vector<std::byte> readbackImage(const Context& ctx, const Image& image, VkImageLayout layout, size_t texelBytes,
                                     std::string& error);

// The first memory type with `flags` among `typeBits`; false (and `error`) when none has them.
bool findMemoryType(const Context& ctx, uint32_t typeBits, VkMemoryPropertyFlags flags, uint32_t& type,
                    std::string& error);

// Layout transition with synchronization2: all mips by default, colour or depth aspect.
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess, VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT, uint32_t baseMip = 0,
                  uint32_t mipCount = VK_REMAINING_MIP_LEVELS);
// Global memory barrier, for buffers and images that keep their layout.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

bool isDepthFormat(VkFormat format);

}  // namespace engine
