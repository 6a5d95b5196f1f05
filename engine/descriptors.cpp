#include "descriptors.h"

namespace engine {

DescriptorSet createDescriptorSet(const Context& ctx, std::span<const Binding> bindings, uint32_t variableCount) {
  DescriptorSet out;
  std::vector<VkDescriptorSetLayoutBinding> vkBindings;
  std::vector<VkDescriptorBindingFlags> flags;
  std::vector<VkDescriptorPoolSize> sizes;
  bool hasVariable = false;
  for (const Binding& b : bindings) {
    VkDescriptorSetLayoutBinding lb{};
    lb.binding = b.binding;
    lb.descriptorType = b.type;
    lb.descriptorCount = b.count;
    lb.stageFlags = VK_SHADER_STAGE_ALL;
    vkBindings.push_back(lb);
    flags.push_back(b.variableCount ? VK_DESCRIPTOR_BINDING_VARIABLE_DESCRIPTOR_COUNT_BIT | VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT
                                    : 0);
    hasVariable |= b.variableCount;
    uint32_t count = b.variableCount ? variableCount : b.count;
    if (count > 0) sizes.push_back({b.type, count});
  }
  VkDescriptorSetLayoutBindingFlagsCreateInfo flagInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  flagInfo.bindingCount = uint32_t(flags.size());
  flagInfo.pBindingFlags = flags.data();
  VkDescriptorSetLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  layoutInfo.pNext = &flagInfo;
  layoutInfo.bindingCount = uint32_t(vkBindings.size());
  layoutInfo.pBindings = vkBindings.data();
  VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &layoutInfo, nullptr, &out.layout));

  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = uint32_t(sizes.size());
  poolInfo.pPoolSizes = sizes.data();
  VK_CHECK(vkCreateDescriptorPool(ctx.device, &poolInfo, nullptr, &out.pool));

  VkDescriptorSetVariableDescriptorCountAllocateInfo variable{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_VARIABLE_DESCRIPTOR_COUNT_ALLOCATE_INFO};
  variable.descriptorSetCount = 1;
  variable.pDescriptorCounts = &variableCount;
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.pNext = hasVariable ? &variable : nullptr;
  alloc.descriptorPool = out.pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &out.layout;
  VK_CHECK(vkAllocateDescriptorSets(ctx.device, &alloc, &out.set));
  return out;
}

void destroyDescriptorSet(const Context& ctx, DescriptorSet& set) {
  if (set.pool) vkDestroyDescriptorPool(ctx.device, set.pool, nullptr);
  if (set.layout) vkDestroyDescriptorSetLayout(ctx.device, set.layout, nullptr);
  set = DescriptorSet{};
}

DescriptorWriter& DescriptorWriter::buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer) {
  buffers_.push_back({buffer, 0, VK_WHOLE_SIZE});
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = &buffers_.back();
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::storageImage(uint32_t binding, VkImageView view, uint32_t arrayElement) {
  images_.push_back({VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL});
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.dstArrayElement = arrayElement;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  w.pImageInfo = &images_.back();
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::sampledImage(uint32_t binding, VkImageView view, VkSampler sampler,
                                                 uint32_t arrayElement) {
  images_.push_back({sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.dstArrayElement = arrayElement;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = &images_.back();
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::uniformTexelBuffer(uint32_t binding, VkBufferView view) {
  texelViews_.push_back(view);
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  w.pTexelBufferView = &texelViews_.back();
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::accelerationStructure(uint32_t binding, const VkAccelerationStructureKHR* as) {
  VkWriteDescriptorSetAccelerationStructureKHR a{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  a.accelerationStructureCount = 1;
  a.pAccelerationStructures = as;
  structures_.push_back(a);
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.pNext = &structures_.back();
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  writes_.push_back(w);
  return *this;
}

void DescriptorWriter::write(const Context& ctx) {
  vkUpdateDescriptorSets(ctx.device, uint32_t(writes_.size()), writes_.data(), 0, nullptr);
  writes_.clear();
}

}  // namespace engine
