// A compute pipeline plus its layout, created from SPIR-V embedded at build
// time. `dispatch` is the one-line call site: it checks the push-constant size
// and rounds the group count up.
#pragma once
#include "context.h"

#include <glm/glm.hpp>
#include <span>

#include "shared/gpu_scene.h"

namespace engine {

struct ComputeProgram {
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  uint32_t pushConstantSize = 0;
  glm::uvec2 groupSize{8, 8};
};

// Specialization constants are 32-bit values with ids 0, 1, 2, ...
ComputeProgram createComputeProgram(const Context& ctx, std::span<const uint32_t> spirv,
                                    std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                                    glm::uvec2 groupSize, std::span<const uint32_t> specialization = {});
void destroyComputeProgram(const Context& ctx, ComputeProgram& program);

// The SPIR-V variant of a scene-reading stage for a traversal backend
// (gpu::TRAVERSAL_*): shaders/CMakeLists.txt builds spv_<stage> with ray
// queries and spv_<stage>_compute with our BVH walk.
inline std::span<const uint32_t> traversalVariant(uint32_t traversal, std::span<const uint32_t> rayQuery,
                                                  std::span<const uint32_t> compute) {
  return traversal == gpu::TRAVERSAL_COMPUTE ? compute : rayQuery;
}
#define GI_SCENE_SPIRV(traversal, stage) engine::traversalVariant(traversal, spv_##stage, spv_##stage##_compute)

VkShaderModule createShaderModule(const Context& ctx, std::span<const uint32_t> spirv);

// Binds the program and its descriptor sets (from set 0), pushes constants and
// dispatches enough groups to cover `threads`.
void dispatch(VkCommandBuffer cmd, const ComputeProgram& program, std::span<const VkDescriptorSet> sets,
              glm::uvec2 threads, const void* pushConstants, uint32_t pushConstantSize);

template <typename T>
void dispatch(VkCommandBuffer cmd, const ComputeProgram& program, std::span<const VkDescriptorSet> sets,
              glm::uvec2 threads, const T& pushConstants) {
  dispatch(cmd, program, sets, threads, &pushConstants, sizeof(T));
}

}  // namespace engine
