#include "gbuffer_pass.h"

#include <cstring>

#include "gbuffer.frag.h"
#include "gbuffer.vert.h"
#include "raster_pipeline.h"

namespace foreign {
namespace {

struct DrawPush {  // gbuffer.vert's Draw block
  glm::mat4 worldFromObject;
  glm::vec4 baseColor, emissionRoughness, metallic;
};
static_assert(sizeof(DrawPush) == 112);

void createPipeline(const example::Host& h, GBufferPass& p) {
  VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.bindingCount = 1;
  setInfo.pBindings = &binding;
  EXAMPLE_CHECK(vkCreateDescriptorSetLayout(h.device, &setInfo, nullptr, &p.setLayout));
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFramesInFlight};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = kFramesInFlight;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  EXAMPLE_CHECK(vkCreateDescriptorPool(h.device, &poolInfo, nullptr, &p.descriptorPool));
  VkDescriptorSetLayout layouts[kFramesInFlight];
  for (VkDescriptorSetLayout& l : layouts) l = p.setLayout;
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = p.descriptorPool;
  alloc.descriptorSetCount = kFramesInFlight;
  alloc.pSetLayouts = layouts;
  EXAMPLE_CHECK(vkAllocateDescriptorSets(h.device, &alloc, p.sets));
  for (uint32_t i = 0; i < kFramesInFlight; ++i) {
    VkDescriptorBufferInfo info{p.uniforms[i].buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = p.sets[i];
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(h.device, 1, &w, 0, nullptr);
  }

  VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(DrawPush)};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &p.setLayout;
  layoutInfo.pushConstantRangeCount = 1;
  layoutInfo.pPushConstantRanges = &push;
  EXAMPLE_CHECK(vkCreatePipelineLayout(h.device, &layoutInfo, nullptr, &p.layout));

  VkVertexInputBindingDescription vertexBinding{0, 24, VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attributes[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                     {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12}};
  VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertexInput.vertexBindingDescriptionCount = 1;
  vertexInput.pVertexBindingDescriptions = &vertexBinding;
  vertexInput.vertexAttributeDescriptionCount = 2;
  vertexInput.pVertexAttributeDescriptions = attributes;
  RasterPipelineDesc pipeline;
  pipeline.layout = p.layout;
  pipeline.vertexCode = spv_gbuffer_vert;
  pipeline.fragmentCode = spv_gbuffer_frag;
  pipeline.vertexInput = &vertexInput;
  pipeline.colorFormats = kTargetFormats;
  pipeline.depthFormat = kDepthFormat;
  p.pipeline = createRasterPipeline(h, pipeline);
}

}  // namespace

gi::GBufferDesc gbufferDesc() {
  gi::GBufferDesc d;
  d.normalFormat = kTargetFormats[kNormal];
  d.normalEncoding = gi::NormalEncoding::Octahedral;
  d.albedoFormat = kTargetFormats[kAlbedo];
  d.glossy = gi::GlossyFlag::FromMaterial;
  d.depthFormat = kDepthFormat;
  d.depthEncoding = gi::DepthEncoding::HardwareReversed;
  d.depthLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  d.colorLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;  // as an engine leaves targets it samples
  d.motion = gi::MotionUnits::Pixels;
  return d;
}

void createGBufferPass(const example::Host& h, const SceneFile& scene, VkExtent2D extent, GBufferPass& p) {
  p.extent = extent;
  for (uint32_t t = 0; t < kTargetCount; ++t)
    p.targets[t] = example::createImage(h, kTargetFormats[t], extent,
                                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                        VK_IMAGE_ASPECT_COLOR_BIT);
  p.depth = example::createImage(h, kDepthFormat, extent,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT);
  // One interleaved vertex buffer and one index buffer for every mesh.
  std::vector<float> vertices;
  std::vector<uint32_t> indices;
  std::vector<std::vector<Draw>> meshDraws;
  for (const Mesh& mesh : scene.meshes) {
    const int32_t base = int32_t(vertices.size() / 6);
    MeshRange& range = p.meshes.emplace_back();
    range.firstVertex = uint32_t(base);
    range.vertexCount = uint32_t(mesh.positions.size());
    range.firstIndex = uint32_t(indices.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v)
      for (const glm::vec3* a : {&mesh.positions[v], &mesh.normals[v]})
        vertices.insert(vertices.end(), {a->x, a->y, a->z});
    std::vector<Draw>& draws = meshDraws.emplace_back();
    for (const gi::PrimitiveDesc& prim : mesh.primitives) {
      draws.push_back({uint32_t(indices.size()), prim.indexCount, base + int32_t(prim.firstVertex), prim.material, {}});
      gi::PrimitiveDesc placed = prim;
      placed.firstIndex = uint32_t(indices.size()) - range.firstIndex;
      range.primitives.push_back(placed);
      indices.insert(indices.end(), mesh.indices.begin() + prim.firstIndex,
                     mesh.indices.begin() + prim.firstIndex + prim.indexCount);
    }
    range.indexCount = uint32_t(indices.size()) - range.firstIndex;
  }
  for (const Instance& inst : scene.instances)
    for (Draw d : meshDraws[inst.mesh]) {
      d.worldFromObject = inst.worldFromObject;
      p.draws.push_back(d);
    }
  p.materials = scene.materials;
  // Device addresses: the module reads its scene from these same buffers.
  p.vertices = example::createBuffer(h, vertices.size() * sizeof(float),
                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                     vertices.data());
  p.indices = example::createBuffer(h, indices.size() * sizeof(uint32_t),
                                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                    indices.data());
  for (example::Buffer& u : p.uniforms)
    u = example::createBuffer(h, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  createPipeline(h, p);
}

void destroyGBufferPass(const example::Host& h, GBufferPass& p) {
  vkDestroyPipeline(h.device, p.pipeline, nullptr);
  vkDestroyPipelineLayout(h.device, p.layout, nullptr);
  vkDestroyDescriptorPool(h.device, p.descriptorPool, nullptr);
  vkDestroyDescriptorSetLayout(h.device, p.setLayout, nullptr);
  for (example::Buffer& u : p.uniforms) example::destroyBuffer(h, u);
  example::destroyBuffer(h, p.vertices);
  example::destroyBuffer(h, p.indices);
  for (example::Image& t : p.targets) example::destroyImage(h, t);
  example::destroyImage(h, p.depth);
}

void recordGBuffer(VkCommandBuffer cmd, GBufferPass& p, uint32_t slot, const FrameUniforms& uniforms) {
  std::memcpy(p.uniforms[slot].mapped, &uniforms, sizeof(uniforms));           // the slot's fence was waited on
  const VkPipelineStageFlags2 reads = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;  // the module read them last frame
  for (example::Image& t : p.targets)
    example::imageBarrier(cmd, t.image, VK_IMAGE_ASPECT_COLOR_BIT,
                          p.initialised ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, reads, 0,
                          VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  example::imageBarrier(cmd, p.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT,
                        p.initialised ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, reads, 0,
                        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  p.initialised = true;

  VkRenderingAttachmentInfo colors[kTargetCount]{};
  for (uint32_t i = 0; i < kTargetCount; ++i) {
    colors[i].sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    colors[i].imageView = p.targets[i].view;
    colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colors[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  }
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = p.depth.view;
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth.clearValue.depthStencil = {0.0f, 0};  // reversed Z: 0 is the background
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, p.extent};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = kTargetCount;
  rendering.pColorAttachments = colors;
  rendering.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &rendering);
  VkViewport viewport{0.0f, 0.0f, float(p.extent.width), float(p.extent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, p.extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout, 0, 1, &p.sets[slot], 0, nullptr);
  VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &p.vertices.buffer, &offset);
  vkCmdBindIndexBuffer(cmd, p.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
  for (const Draw& d : p.draws) {
    const gi::MaterialDesc& m = p.materials[d.material];
    DrawPush push{d.worldFromObject, glm::vec4(m.baseColor[0], m.baseColor[1], m.baseColor[2], m.baseColor[3]),
                  glm::vec4(glm::vec3(m.emissive[0], m.emissive[1], m.emissive[2]) * m.emissiveStrength, m.roughness),
                  glm::vec4(m.metallic, 0.0f, 0.0f, 0.0f)};
    vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push),
                       &push);
    vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
  }
  vkCmdEndRendering(cmd);
  for (example::Image& t : p.targets)
    example::imageBarrier(cmd, t.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                          VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  example::imageBarrier(cmd, p.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

gi::GBufferViews gbufferViews(const GBufferPass& p) {
  return {p.targets[kNormal].view,   p.targets[kAlbedo].view, p.targets[kMaterial].view,
          p.targets[kEmission].view, p.targets[kMotion].view, p.depth.view};
}

}  // namespace foreign

namespace foreign {

std::vector<gi::MeshDesc> deviceMeshes(const example::Host& h, const GBufferPass& p) {
  auto address = [&](const example::Buffer& b) {
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = b.buffer;
    return vkGetBufferDeviceAddress(h.device, &info);
  };
  const VkDeviceAddress vertices = address(p.vertices), indices = address(p.indices);
  std::vector<gi::MeshDesc> out;
  for (const MeshRange& range : p.meshes) {
    gi::MeshDesc d;
    d.vertexCount = range.vertexCount;
    d.indexCount = range.indexCount;
    d.primitives = range.primitives;
    d.device.positions = {vertices + VkDeviceAddress(range.firstVertex) * 24, VK_FORMAT_R32G32B32_SFLOAT, 24};
    d.device.normals = {vertices + VkDeviceAddress(range.firstVertex) * 24 + 12, VK_FORMAT_R32G32B32_SFLOAT, 24};
    d.device.indices = indices + VkDeviceAddress(range.firstIndex) * 4;
    d.device.indexType = VK_INDEX_TYPE_UINT32;
    out.push_back(d);
  }
  return out;
}

}  // namespace foreign
