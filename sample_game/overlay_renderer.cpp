#include "overlay_renderer.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>

#include "graphics_pipeline.h"
#include "overlay.frag.h"
#include "overlay.vert.h"
#include "shared/display.h"

namespace demo {
namespace {

VkPipeline createPipeline(const engine::Context& ctx, VkPipelineLayout layout, VkFormat format, std::string& error) {
  const VkVertexInputBindingDescription binding{0, sizeof(ImDrawVert), VK_VERTEX_INPUT_RATE_VERTEX};
  const VkVertexInputAttributeDescription attributes[] = {
      {0, 0, VK_FORMAT_R32G32_SFLOAT, uint32_t(offsetof(ImDrawVert, pos))},
      {1, 0, VK_FORMAT_R32G32_SFLOAT, uint32_t(offsetof(ImDrawVert, uv))},
      {2, 0, VK_FORMAT_R8G8B8A8_UNORM, uint32_t(offsetof(ImDrawVert, col))},
  };
  VkPipelineColorBlendAttachmentState blend{};
  blend.blendEnable = VK_TRUE;  // ImGui's "over" operator with its alpha
  blend.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
  blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
  blend.colorBlendOp = VK_BLEND_OP_ADD;
  blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
  blend.alphaBlendOp = VK_BLEND_OP_ADD;
  blend.colorWriteMask = 0xf;
  engine::GraphicsPipelineDesc desc;
  desc.layout = layout;
  desc.vertexSpirv = spv_overlay_vert;
  desc.fragmentSpirv = spv_overlay_frag;
  desc.vertexBindings = std::span(&binding, 1);
  desc.vertexAttributes = attributes;
  desc.colorFormats = std::span(&format, 1);
  desc.blends = std::span(&blend, 1);
  return engine::createGraphicsPipeline(ctx, desc, error);
}

// A host-visible buffer of at least `bytes` (grown by half again to avoid regrowing every frame).
bool ensureCapacity(const engine::Context& ctx, engine::Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage,
                    std::string& error) {
  if (buffer.buffer && buffer.size >= bytes) return true;
  if (buffer.buffer) engine::destroyBuffer(ctx, buffer);
  buffer = engine::createBuffer(ctx, std::max<VkDeviceSize>(bytes + bytes / 2, 4096), usage,
                                engine::MemoryKind::HostVisible, error);
  return error.empty();
}

}  // namespace

OverlayRenderer createOverlayRenderer(const engine::Context& ctx, VkFormat targetFormat, std::string& error) {
  OverlayRenderer r;
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  ImGui::GetIO().Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
  r.font = engine::createImage(ctx, {uint32_t(width), uint32_t(height)}, VK_FORMAT_R8G8B8A8_UNORM,
                               VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, error);
  engine::uploadImage(ctx, r.font, pixels, size_t(width) * size_t(height) * 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      error);
  VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  s.magFilter = s.minFilter = VK_FILTER_LINEAR;
  s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  if (error.empty())
    VK_SUCCEEDED(error, "the overlay's font sampler", vkCreateSampler(ctx.device, &s, nullptr, &r.sampler));
  const engine::Binding bindings[] = {{gpu::OVERLAY_BINDING_FONT, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}};
  r.set = engine::createDescriptorSet(ctx, bindings, error);
  if (!error.empty()) {
    destroyOverlayRenderer(ctx, r);
    return r;
  }
  engine::DescriptorWriter(r.set.set).sampledImage(gpu::OVERLAY_BINDING_FONT, r.font.view, r.sampler).write(ctx.vk);

  VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(gpu::OverlayPush)};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &r.set.layout;
  layoutInfo.pushConstantRangeCount = 1;
  layoutInfo.pPushConstantRanges = &range;
  VK_SUCCEEDED(error, "the overlay's pipeline", vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &r.layout));
  r.pipeline = createPipeline(ctx, r.layout, targetFormat, error);
  if (!error.empty()) {
    destroyOverlayRenderer(ctx, r);
    return r;
  }
  ImGui::GetIO().Fonts->SetTexID(reinterpret_cast<ImTextureID>(r.set.set));
  return r;
}

void destroyOverlayRenderer(const engine::Context& ctx, OverlayRenderer& r) {
  if (r.pipeline) vkDestroyPipeline(ctx.device, r.pipeline, nullptr);
  if (r.layout) vkDestroyPipelineLayout(ctx.device, r.layout, nullptr);
  if (r.sampler) vkDestroySampler(ctx.device, r.sampler, nullptr);
  engine::destroyDescriptorSet(ctx, r.set);
  engine::destroyImage(ctx, r.font);
  for (int i = 0; i < 2; ++i)
    for (engine::Buffer* b : {&r.vertices[i], &r.indices[i]})
      if (b->buffer) engine::destroyBuffer(ctx, *b);
  r = OverlayRenderer{};
}

bool recordOverlay(const engine::Context& ctx, VkCommandBuffer cmd, OverlayRenderer& r, uint32_t frameIndex,
                   const ImDrawData& data, VkImage target, VkImageView targetView, VkExtent2D extent,
                   std::string& error) {
  if (data.TotalVtxCount == 0) return true;
  engine::Buffer& vertices = r.vertices[frameIndex % 2];
  engine::Buffer& indices = r.indices[frameIndex % 2];
  if (!ensureCapacity(ctx, vertices, sizeof(ImDrawVert) * size_t(data.TotalVtxCount), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                      error) ||
      !ensureCapacity(ctx, indices, sizeof(ImDrawIdx) * size_t(data.TotalIdxCount), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                      error))
    return false;
  auto* vertexOut = static_cast<ImDrawVert*>(vertices.mapped);
  auto* indexOut = static_cast<ImDrawIdx*>(indices.mapped);
  for (int i = 0; i < data.CmdListsCount; ++i) {
    const ImDrawList* list = data.CmdLists[i];
    std::memcpy(vertexOut, list->VtxBuffer.Data, sizeof(ImDrawVert) * size_t(list->VtxBuffer.Size));
    std::memcpy(indexOut, list->IdxBuffer.Data, sizeof(ImDrawIdx) * size_t(list->IdxBuffer.Size));
    vertexOut += list->VtxBuffer.Size;
    indexOut += list->IdxBuffer.Size;
  }

  // Whatever wrote the target (a compute pass) finishes before the overlay blends onto it.
  engine::imageBarrier(cmd, target, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = targetView;
  color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, extent};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachments = &color;
  vkCmdBeginRendering(cmd, &rendering);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r.layout, 0, 1, &r.set.set, 0, nullptr);
  VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertices.buffer, &offset);
  vkCmdBindIndexBuffer(cmd, indices.buffer, 0, sizeof(ImDrawIdx) == 2 ? VK_INDEX_TYPE_UINT16 : VK_INDEX_TYPE_UINT32);
  VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  gpu::OverlayPush push{
      {2.0f / data.DisplaySize.x, 2.0f / data.DisplaySize.y},
      {-1.0f - data.DisplayPos.x * 2.0f / data.DisplaySize.x, -1.0f - data.DisplayPos.y * 2.0f / data.DisplaySize.y}};
  vkCmdPushConstants(cmd, r.layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
  int32_t vertexBase = 0;
  uint32_t indexBase = 0;
  for (int i = 0; i < data.CmdListsCount; ++i) {
    const ImDrawList* list = data.CmdLists[i];
    for (const ImDrawCmd& c : list->CmdBuffer) {
      // Clip rectangle in framebuffer pixels, clamped to the image.
      float x0 = std::max(c.ClipRect.x - data.DisplayPos.x, 0.0f),
            y0 = std::max(c.ClipRect.y - data.DisplayPos.y, 0.0f);
      float x1 = std::min(c.ClipRect.z - data.DisplayPos.x, float(extent.width));
      float y1 = std::min(c.ClipRect.w - data.DisplayPos.y, float(extent.height));
      if (x1 <= x0 || y1 <= y0) continue;
      VkRect2D scissor{{int32_t(x0), int32_t(y0)}, {uint32_t(x1 - x0), uint32_t(y1 - y0)}};
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdDrawIndexed(cmd, c.ElemCount, 1, indexBase + c.IdxOffset, vertexBase + int32_t(c.VtxOffset), 0);
    }
    vertexBase += list->VtxBuffer.Size;
    indexBase += uint32_t(list->IdxBuffer.Size);
  }
  vkCmdEndRendering(cmd);
  engine::imageBarrier(cmd, target, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                       VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  return true;
}

}  // namespace demo
