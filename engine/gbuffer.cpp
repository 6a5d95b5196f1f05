#include "gbuffer.h"

#include "graphics_pipeline.h"

#include <cstring>

#include "gbuffer.frag.h"
#include "gbuffer.vert.h"

namespace engine {

gi::GBufferDesc moduleGBufferDesc() {
  gi::GBufferDesc g;
  g.glossy = gi::GlossyFlag::AlbedoAlpha;
  return g;
}

GBuffer createGBuffer(const Context& ctx, VkExtent2D extent, std::string& error) {
  GBuffer g;
  g.extent = g.renderExtent = extent;
  for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i)
    g.color[i] =
        createImage(ctx, extent, kGBufferFormats[i],
                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                        VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                    error);
  g.depth = createImage(ctx, extent, kGBufferDepthFormat,
                        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, error);
  // Start in the post-pass layout so recordGBuffer always transitions from GENERAL.
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        for (Image& img : g.color)
          imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, 0,
                       VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
        imageBarrier(cmd, g.depth.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT,
                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
      },
      error);
  if (!error.empty()) destroyGBuffer(ctx, g);
  return g;
}

void destroyGBuffer(const Context& ctx, GBuffer& g) {
  for (Image& img : g.color) destroyImage(ctx, img);
  destroyImage(ctx, g.depth);
  g = GBuffer{};
}

GBufferPass createGBufferPass(const Context& ctx, const SceneGpu& scene, std::string& error) {
  GBufferPass p;
  if (!error.empty()) return p;
  const Binding cameraBinding[] = {{gpu::GBUFFER_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}};
  p.cameraSet = createDescriptorSet(ctx, cameraBinding, error);
  p.cameraBuffer =
      createBuffer(ctx, sizeof(gpu::GpuCamera), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                   MemoryKind::DeviceLocal, error);
  if (!error.empty()) {
    destroyGBufferPass(ctx, p);
    return p;
  }
  DescriptorWriter(p.cameraSet.set)
      .buffer(gpu::GBUFFER_BINDING_CAMERA, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, p.cameraBuffer.buffer)
      .write(ctx.vk);

  VkDescriptorSetLayout sets[] = {scene.set.layout, p.cameraSet.layout};
  VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(gpu::GBufferPush)};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 2;
  layoutInfo.pSetLayouts = sets;
  layoutInfo.pushConstantRangeCount = 1;
  layoutInfo.pPushConstantRanges = &range;
  VK_SUCCEEDED(error, "the G-buffer pass", vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &p.layout));

  VkPipelineColorBlendAttachmentState blend[gpu::GBUFFER_COLOR_COUNT]{};
  for (auto& b : blend) b.colorWriteMask = 0xf;
  GraphicsPipelineDesc desc;
  desc.layout = p.layout;
  desc.vertexSpirv = spv_gbuffer_vert;  // vertices are pulled from the scene's buffers
  desc.fragmentSpirv = spv_gbuffer_frag;
  desc.colorFormats = kGBufferFormats;
  desc.blends = blend;
  desc.depthFormat = kGBufferDepthFormat;
  desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed Z (camera.cpp)
  p.pipeline = createGraphicsPipeline(ctx, desc, error);
  if (!error.empty()) destroyGBufferPass(ctx, p);
  return p;
}

void destroyGBufferPass(const Context& ctx, GBufferPass& p) {
  if (p.pipeline) vkDestroyPipeline(ctx.device, p.pipeline, nullptr);
  if (p.layout) vkDestroyPipelineLayout(ctx.device, p.layout, nullptr);
  destroyDescriptorSet(ctx, p.cameraSet);
  destroyBuffer(ctx, p.cameraBuffer);
  p = GBufferPass{};
}

void recordGBuffer(const Context& ctx, VkCommandBuffer cmd, GBufferPass& pass, const Scene& scene,
                   const SceneGpu& sceneGpu, const GBuffer& g, const gpu::GpuCamera& camera, GpuTimer* timer) {
  if (timer) beginPass(ctx, cmd, *timer, "gbuffer");
  // The camera is written in the command buffer, not by the host: frames in
  // flight each see their own (after the previous frame's draws read it).
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0,
                VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdUpdateBuffer(cmd, pass.cameraBuffer.buffer, 0, sizeof(camera), &camera);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                VK_ACCESS_2_UNIFORM_READ_BIT);
  for (const Image& img : g.color)
    imageBarrier(cmd, img.image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  imageBarrier(cmd, g.depth.image, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
               VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
               VK_IMAGE_ASPECT_DEPTH_BIT);

  VkRenderingAttachmentInfo colors[gpu::GBUFFER_COLOR_COUNT]{};
  for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i) {
    colors[i].sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    colors[i].imageView = g.color[i].view;
    colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colors[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colors[i].clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
  }
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = g.depth.view;
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth.clearValue.depthStencil = {0.0f, 0};  // reversed Z: 0 is infinitely far
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, g.renderExtent};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = gpu::GBUFFER_COLOR_COUNT;
  rendering.pColorAttachments = colors;
  rendering.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &rendering);
  VkViewport viewport{0.0f, 0.0f, float(g.renderExtent.width), float(g.renderExtent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, g.renderExtent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.pipeline);
  VkDescriptorSet sets[] = {sceneGpu.set.set, pass.cameraSet.set};
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.layout, 0, 2, sets, 0, nullptr);
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
      gpu::GBufferPush push{i, p};
      vkCmdPushConstants(cmd, pass.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push),
                         &push);
      if (scene.primitives[p].indexCount > 0) vkCmdDraw(cmd, scene.primitives[p].indexCount, 1, 0, 0);
    }
  }
  vkCmdEndRendering(cmd);
  for (const Image& img : g.color)
    imageBarrier(
        cmd, img.image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
        VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
  if (timer) endPass(ctx, cmd, *timer);
}

}  // namespace engine
