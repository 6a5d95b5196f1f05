// Descriptor set helpers: a layout from a binding list, a pool sized for it,
// and a writer that batches updates. Each pass owns its own set(s).
#pragma once
#include "context.h"

#include <deque>
#include <span>
#include <vector>

namespace engine {

struct Binding {
  uint32_t binding;
  VkDescriptorType type;
  uint32_t count = 1;            // upper bound when variableCount
  bool variableCount = false;    // last binding only: a runtime-sized array
};

struct DescriptorSet {
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
};

// Creates a layout (all stages), a pool and one set. `variableCount` is the
// actual size of the variable-count binding, if there is one.
DescriptorSet createDescriptorSet(const Context& ctx, std::span<const Binding> bindings, uint32_t variableCount = 0);
void destroyDescriptorSet(const Context& ctx, DescriptorSet& set);

class DescriptorWriter {
 public:
  explicit DescriptorWriter(VkDescriptorSet set) : set_(set) {}
  DescriptorWriter& buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer);
  DescriptorWriter& storageImage(uint32_t binding, VkImageView view, uint32_t arrayElement = 0);
  DescriptorWriter& sampledImage(uint32_t binding, VkImageView view, VkSampler sampler, uint32_t arrayElement = 0);
  DescriptorWriter& accelerationStructure(uint32_t binding, const VkAccelerationStructureKHR* as);
  DescriptorWriter& uniformTexelBuffer(uint32_t binding, VkBufferView view);
  void write(const Context& ctx);

 private:
  VkDescriptorSet set_;
  std::vector<VkWriteDescriptorSet> writes_;
  std::deque<VkDescriptorBufferInfo> buffers_;  // deques keep element addresses stable
  std::deque<VkDescriptorImageInfo> images_;
  std::deque<VkWriteDescriptorSetAccelerationStructureKHR> structures_;
  std::deque<VkBufferView> texelViews_;
};

}  // namespace engine
