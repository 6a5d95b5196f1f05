// The foreign engine's graphics pipelines (the G-buffer raster and the present pass): dynamic rendering,
// dynamic viewport and scissor, no culling, one sample, every colour channel written.
#pragma once
#include <span>

#include "vulkan_host.h"

namespace foreign {

struct RasterPipelineDesc {
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::span<const uint32_t> vertexCode, fragmentCode;                 // SPIR-V words
  const VkPipelineVertexInputStateCreateInfo* vertexInput = nullptr;  // null: no vertex buffers
  std::span<const VkFormat> colorFormats;
  VkFormat depthFormat = VK_FORMAT_UNDEFINED;        // set: depth tested with depthCompare and written
  VkCompareOp depthCompare = VK_COMPARE_OP_GREATER;  // reversed Z: 1 near, 0 infinitely far
};

VkPipeline createRasterPipeline(const example::Host& h, const RasterPipelineDesc& desc);

}  // namespace foreign
