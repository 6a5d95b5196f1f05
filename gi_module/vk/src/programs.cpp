#include "gi/vk/programs.h"

namespace gi::vk {

Status createComputeProgram(const Device& d, std::span<const uint32_t> spirv,
                            std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                            glm::uvec2 groupSize, std::span<const uint32_t> specialization, ComputeProgram& out) {
  ComputeProgram p;
  p.pushConstantSize = pushConstantSize;
  p.groupSize = groupSize;
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantSize};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = uint32_t(setLayouts.size());
  layoutInfo.pSetLayouts = setLayouts.data();
  layoutInfo.pushConstantRangeCount = pushConstantSize > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  GI_VK(d.fn.vkCreatePipelineLayout(d.device, &layoutInfo, d.allocator, &p.layout));

  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < specialization.size(); ++i) entries.push_back({i, i * 4u, 4});
  VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), specialization.size_bytes(),
                            specialization.data()};
  VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  moduleInfo.codeSize = spirv.size_bytes();
  moduleInfo.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  VkResult r = d.fn.vkCreateShaderModule(d.device, &moduleInfo, d.allocator, &module);
  if (r == VK_SUCCESS) {
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = specialization.empty() ? nullptr : &spec;
    info.layout = p.layout;
    r = d.fn.vkCreateComputePipelines(d.device, d.pipelineCache, 1, &info, d.allocator, &p.pipeline);
    d.fn.vkDestroyShaderModule(d.device, module, d.allocator);
    if (r != VK_SUCCESS) p.pipeline = VK_NULL_HANDLE;
  }
  if (r != VK_SUCCESS) {
    destroyComputeProgram(d, p);
    return {r, module ? "vkCreateComputePipelines" : "vkCreateShaderModule"};
  }
  out = p;
  return {};
}

void destroyComputeProgram(const Device& d, ComputeProgram& p) {
  if (p.pipeline) d.fn.vkDestroyPipeline(d.device, p.pipeline, d.allocator);
  if (p.layout) d.fn.vkDestroyPipelineLayout(d.device, p.layout, d.allocator);
  p = ComputeProgram{};
}

void dispatch(const Device& d, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* pushConstants,
              uint32_t pushConstantSize) {
  d.fn.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline);
  if (!sets.empty())
    d.fn.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout, 0, uint32_t(sets.size()),
                                 sets.data(), 0, nullptr);
  if (pushConstantSize > 0)
    d.fn.vkCmdPushConstants(cmd, program.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantSize, pushConstants);
  glm::uvec2 groups = (threads + program.groupSize - 1u) / program.groupSize;
  if (groups.x > 0 && groups.y > 0) d.fn.vkCmdDispatch(cmd, groups.x, groups.y, 1);
}

void warmUp(const Device& d, VkCommandBuffer cmd, const ComputeProgram& program,
            std::span<const VkDescriptorSet> sets) {
  static constexpr uint8_t kZeros[256] = {};  // every push struct is far smaller (maxPushConstantsSize >= 128)
  d.fn.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline);
  if (!sets.empty())
    d.fn.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout, 0, uint32_t(sets.size()),
                                 sets.data(), 0, nullptr);
  if (program.pushConstantSize > 0)
    d.fn.vkCmdPushConstants(cmd, program.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, program.pushConstantSize, kZeros);
  d.fn.vkCmdDispatch(cmd, 0, 0, 0);
}

Status createDescriptorLayout(const Device& d, std::span<const Binding> bindings, VkDescriptorSetLayout& out) {
  std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
  std::vector<VkDescriptorBindingFlags> flags;
  for (const Binding& b : bindings) {
    layoutBindings.push_back({b.binding, b.type, b.count, VK_SHADER_STAGE_ALL, nullptr});
    flags.push_back(b.variableCount ? VK_DESCRIPTOR_BINDING_VARIABLE_DESCRIPTOR_COUNT_BIT |
                                          VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT
                                    : 0);
  }
  VkDescriptorSetLayoutBindingFlagsCreateInfo flagInfo{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  flagInfo.bindingCount = uint32_t(flags.size());
  flagInfo.pBindingFlags = flags.data();
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.pNext = &flagInfo;
  info.bindingCount = uint32_t(layoutBindings.size());
  info.pBindings = layoutBindings.data();
  GI_VK(d.fn.vkCreateDescriptorSetLayout(d.device, &info, d.allocator, &out));
  return {};
}

Status createDescriptorSets(const Device& d, std::span<const Binding> bindings, uint32_t count, DescriptorSets& out,
                            VkDescriptorSetLayout layout, uint32_t variableCount) {
  DescriptorSets s;
  if (d.memory.simulate) {  // a memory prediction: sets hold no device memory of the module's
    s.sets.assign(count, VK_NULL_HANDLE);
    out = std::move(s);
    return {};
  }
  auto build = [&]() -> Status {
    if (layout) {
      s.layout = layout;
    } else {
      GI_TRY(createDescriptorLayout(d, bindings, s.layout));
      s.ownsLayout = true;
    }
    std::vector<VkDescriptorPoolSize> sizes;
    bool variable = false;
    for (const Binding& b : bindings) {
      const uint32_t n = b.variableCount ? variableCount : b.count;
      variable |= b.variableCount;
      if (n > 0) sizes.push_back({b.type, n * count});
    }
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = count;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    GI_VK(d.fn.vkCreateDescriptorPool(d.device, &poolInfo, d.allocator, &s.pool));
    std::vector<VkDescriptorSetLayout> layouts(count, s.layout);
    std::vector<uint32_t> counts(count, variableCount);
    s.sets.resize(count);
    VkDescriptorSetVariableDescriptorCountAllocateInfo variableInfo{
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_VARIABLE_DESCRIPTOR_COUNT_ALLOCATE_INFO};
    variableInfo.descriptorSetCount = count;
    variableInfo.pDescriptorCounts = counts.data();
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.pNext = variable ? &variableInfo : nullptr;
    alloc.descriptorPool = s.pool;
    alloc.descriptorSetCount = count;
    alloc.pSetLayouts = layouts.data();
    GI_VK(d.fn.vkAllocateDescriptorSets(d.device, &alloc, s.sets.data()));
    return {};
  };
  if (Status status = build()) {
    destroyDescriptorSets(d, s);
    return status;
  }
  out = std::move(s);
  return {};
}

void destroyDescriptorSets(const Device& d, DescriptorSets& s) {
  if (s.pool) d.fn.vkDestroyDescriptorPool(d.device, s.pool, d.allocator);
  if (s.layout && s.ownsLayout) d.fn.vkDestroyDescriptorSetLayout(d.device, s.layout, d.allocator);
  s = DescriptorSets{};
}

VkWriteDescriptorSet& DescriptorWriter::add(uint32_t binding, VkDescriptorType type, uint32_t arrayElement) {
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.dstArrayElement = arrayElement;
  w.descriptorCount = 1;
  w.descriptorType = type;
  writes_.push_back(w);
  return writes_.back();
}

DescriptorWriter& DescriptorWriter::buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                                           VkDeviceSize offset, VkDeviceSize range) {
  buffers_.push_back({buffer, offset, range});
  add(binding, type).pBufferInfo = &buffers_.back();
  return *this;
}

DescriptorWriter& DescriptorWriter::storageImage(uint32_t binding, VkImageView view, uint32_t arrayElement) {
  images_.push_back({VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL});
  add(binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, arrayElement).pImageInfo = &images_.back();
  return *this;
}

DescriptorWriter& DescriptorWriter::sampledImage(uint32_t binding, VkImageView view, VkSampler sampler,
                                                 uint32_t arrayElement) {
  images_.push_back({sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  add(binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, arrayElement).pImageInfo = &images_.back();
  return *this;
}

DescriptorWriter& DescriptorWriter::texture(uint32_t binding, VkImageView view, VkImageLayout layout) {
  images_.push_back({VK_NULL_HANDLE, view, layout});
  add(binding, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE).pImageInfo = &images_.back();
  return *this;
}

DescriptorWriter& DescriptorWriter::accelerationStructure(uint32_t binding,
                                                          const VkAccelerationStructureKHR* structure) {
  VkWriteDescriptorSetAccelerationStructureKHR a{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  a.accelerationStructureCount = 1;
  a.pAccelerationStructures = structure;
  structures_.push_back(a);
  add(binding, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR).pNext = &structures_.back();
  return *this;
}

DescriptorWriter& DescriptorWriter::uniformTexelBuffer(uint32_t binding, VkBufferView view) {
  texelViews_.push_back(view);
  add(binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER).pTexelBufferView = &texelViews_.back();
  return *this;
}

void DescriptorWriter::write(const Device& d) {
  if (!writes_.empty() && !d.memory.simulate)
    d.fn.vkUpdateDescriptorSets(d.device, uint32_t(writes_.size()), writes_.data(), 0, nullptr);
  writes_.clear();
}

}  // namespace gi::vk
