#include "present_pass.h"

#include "present.frag.h"
#include "present.vert.h"
#include "raster_pipeline.h"

namespace foreign {
namespace {

void createSet(const example::Host& h, VkImageView output, PresentPass& p) {
  VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
  EXAMPLE_CHECK(vkCreateSampler(h.device, &samplerInfo, nullptr, &p.sampler));
  VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT,
                                       nullptr};
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.bindingCount = 1;
  setInfo.pBindings = &binding;
  EXAMPLE_CHECK(vkCreateDescriptorSetLayout(h.device, &setInfo, nullptr, &p.setLayout));
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  EXAMPLE_CHECK(vkCreateDescriptorPool(h.device, &poolInfo, nullptr, &p.descriptorPool));
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = p.descriptorPool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &p.setLayout;
  EXAMPLE_CHECK(vkAllocateDescriptorSets(h.device, &alloc, &p.set));
  VkDescriptorImageInfo image{p.sampler, output, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = p.set;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = &image;
  vkUpdateDescriptorSets(h.device, 1, &w, 0, nullptr);
}

void createPipeline(const example::Host& h, PresentPass& p) {
  VkPushConstantRange push{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(float)};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &p.setLayout;
  layoutInfo.pushConstantRangeCount = 1;
  layoutInfo.pPushConstantRanges = &push;
  EXAMPLE_CHECK(vkCreatePipelineLayout(h.device, &layoutInfo, nullptr, &p.layout));
  RasterPipelineDesc pipeline;
  pipeline.layout = p.layout;
  pipeline.vertexCode = spv_present_vert;
  pipeline.fragmentCode = spv_present_frag;
  pipeline.colorFormats = std::span(&kPresentFormat, 1);
  p.pipeline = createRasterPipeline(h, pipeline);
}

}  // namespace

void createPresentPass(const example::Host& h, VkExtent2D extent, VkImageView output, PresentPass& p) {
  p.extent = extent;
  for (example::Image& t : p.targets)
    t = example::createImage(h, kPresentFormat, extent,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                             VK_IMAGE_ASPECT_COLOR_BIT);
  createSet(h, output, p);
  createPipeline(h, p);
}

void destroyPresentPass(const example::Host& h, PresentPass& p) {
  vkDestroyPipeline(h.device, p.pipeline, nullptr);
  vkDestroyPipelineLayout(h.device, p.layout, nullptr);
  vkDestroyDescriptorPool(h.device, p.descriptorPool, nullptr);
  vkDestroyDescriptorSetLayout(h.device, p.setLayout, nullptr);
  vkDestroySampler(h.device, p.sampler, nullptr);
  for (example::Image& t : p.targets) example::destroyImage(h, t);
  p = PresentPass{};
}

void recordPresent(VkCommandBuffer cmd, const PresentPass& p, uint32_t slot, float scale,
                   const example::Buffer& readback) {
  const example::Image& target = p.targets[slot];
  // The slot's last copy completed before its fence signalled: its contents may go.
  example::imageBarrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = target.view;
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is drawn
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, p.extent};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachments = &color;
  vkCmdBeginRendering(cmd, &rendering);
  VkViewport viewport{0.0f, 0.0f, float(p.extent.width), float(p.extent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, p.extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout, 0, 1, &p.set, 0, nullptr);
  const float inverseScale = 1.0f / scale;
  vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(inverseScale), &inverseScale);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  example::imageBarrier(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                        VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                        VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {p.extent.width, p.extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, target.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &region);
  example::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

}  // namespace foreign
