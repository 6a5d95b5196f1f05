// A graphics pipeline for dynamic rendering from the few things that differ
// between our raster passes (the G-buffer, the demo's overlay): shaders,
// vertex input, colour formats and blending, depth. Viewport and scissor are
// dynamic; triangles are filled, never culled.
#pragma once
#include <span>
#include <string>

#include "context.h"

namespace engine {

struct GraphicsPipelineDesc {
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::span<const uint32_t> vertexSpirv, fragmentSpirv;
  std::span<const VkVertexInputBindingDescription> vertexBindings;  // empty: vertices pulled from buffers
  std::span<const VkVertexInputAttributeDescription> vertexAttributes;
  std::span<const VkFormat> colorFormats;
  std::span<const VkPipelineColorBlendAttachmentState> blends;  // one per colour format
  VkFormat depthFormat = VK_FORMAT_UNDEFINED;                   // UNDEFINED: no depth attachment
  VkCompareOp depthCompare = VK_COMPARE_OP_GREATER;             // reversed Z (camera.cpp)
};

// Errors as in vk.h: null and `error`.
VkPipeline createGraphicsPipeline(const Context& ctx, const GraphicsPipelineDesc& desc, std::string& error);

}  // namespace engine
