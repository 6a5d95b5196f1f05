// Compute programs (pipeline + layout from embedded SPIR-V) and descriptor
// sets: a layout from a binding list, pools of sets of it, a batching writer.
// The module's own; the sample engine builds its passes on the same pieces.
#pragma once
#include <deque>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "gi/vk/device.h"
#include "shared/gpu_scene.h"

namespace gi::vk {

struct ComputeProgram {
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  uint32_t pushConstantSize = 0;
  glm::uvec2 groupSize{8, 8};
};

// Specialization constants are 32-bit values with ids 0, 1, 2, ...; the
// pipeline goes through the engine's pipeline cache, if it gave one.
Status createComputeProgram(const Device& device, std::span<const uint32_t> spirv,
                            std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                            glm::uvec2 groupSize, std::span<const uint32_t> specialization, ComputeProgram& out);
void destroyComputeProgram(const Device& device, ComputeProgram& program);

// Binds the program and its sets (from set 0), pushes constants and
// dispatches enough groups to cover `threads`. The push size must match.
void dispatch(const Device& device, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* pushConstants,
              uint32_t pushConstantSize);
template <typename T>
void dispatch(const Device& device, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const T& pushConstants) {
  dispatch(device, cmd, program, sets, threads, &pushConstants, sizeof(T));
}

// Binds the program and its sets, pushes zeros and dispatches no workgroups:
// nothing runs, but a driver that compiles at a program's first dispatch
// (lavapipe) compiles it here, so a timed or latency-bound dispatch later does not.
void warmUp(const Device& device, VkCommandBuffer cmd, const ComputeProgram& program,
            std::span<const VkDescriptorSet> sets);

// The SPIR-V of a scene-reading stage for a traversal backend (gpu::TRAVERSAL_*):
// spv_<stage> traces with ray queries, spv_<stage>_compute walks our BVH.
inline std::span<const uint32_t> traversalVariant(uint32_t traversal, std::span<const uint32_t> rayQuery,
                                                  std::span<const uint32_t> compute) {
  return traversal == gpu::TRAVERSAL_COMPUTE ? compute : rayQuery;
}
#define GI_SCENE_SPIRV(traversal, stage) ::gi::vk::traversalVariant(traversal, spv_##stage, spv_##stage##_compute)

struct Binding {
  uint32_t binding;
  VkDescriptorType type;
  uint32_t count = 1;          // upper bound when variableCount
  bool variableCount = false;  // last binding only: a runtime-sized, partially bound array
};

// `count` sets of one layout, from a pool of their own.
struct DescriptorSets {
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> sets;
  bool ownsLayout = false;
  VkDescriptorSet operator[](size_t i) const { return sets[i]; }
};
Status createDescriptorLayout(const Device& device, std::span<const Binding> bindings, VkDescriptorSetLayout& out);
// With `layout` given (made from the same bindings) the sets use it and do
// not own it. `variableCount`: the size of the variable-count binding, if any.
Status createDescriptorSets(const Device& device, std::span<const Binding> bindings, uint32_t count,
                            DescriptorSets& out, VkDescriptorSetLayout layout = VK_NULL_HANDLE,
                            uint32_t variableCount = 0);
void destroyDescriptorSets(const Device& device, DescriptorSets& sets);

class DescriptorWriter {
 public:
  explicit DescriptorWriter(VkDescriptorSet set) : set_(set) {}
  DescriptorWriter& buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer, VkDeviceSize offset = 0,
                           VkDeviceSize range = VK_WHOLE_SIZE);
  DescriptorWriter& storageImage(uint32_t binding, VkImageView view, uint32_t arrayElement = 0);
  DescriptorWriter& sampledImage(uint32_t binding, VkImageView view, VkSampler sampler, uint32_t arrayElement = 0);
  // VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE: read with texelFetch, no sampler.
  DescriptorWriter& texture(uint32_t binding, VkImageView view, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);
  DescriptorWriter& accelerationStructure(uint32_t binding, const VkAccelerationStructureKHR* structure);
  DescriptorWriter& uniformTexelBuffer(uint32_t binding, VkBufferView view);
  void write(const Device& device);

 private:
  VkWriteDescriptorSet& add(uint32_t binding, VkDescriptorType type, uint32_t arrayElement = 0);
  VkDescriptorSet set_;
  std::vector<VkWriteDescriptorSet> writes_;
  std::deque<VkDescriptorBufferInfo> buffers_;  // deques keep element addresses stable
  std::deque<VkDescriptorImageInfo> images_;
  std::deque<VkWriteDescriptorSetAccelerationStructureKHR> structures_;
  std::deque<VkBufferView> texelViews_;
};

}  // namespace gi::vk
