// The engine's compute passes on the GI module's Vulkan layer (gi/vk/programs.h):
// the same programs, with the engine's error style (vk.h). `dispatch` is the
// one-line call site: it checks the push-constant size and rounds the group
// count up.
#pragma once
#include "context.h"

#include <glm/glm.hpp>
#include <span>
#include <string>

#include "gi/vk/programs.h"

namespace engine {

using ComputeProgram = gi::vk::ComputeProgram;

// Specialization constants are 32-bit values with ids 0, 1, 2, ... Errors as in vk.h: an empty program.
ComputeProgram createComputeProgram(const Context& ctx, std::span<const uint32_t> spirv,
                                    std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                                    glm::uvec2 groupSize, std::string& error,
                                    std::span<const uint32_t> specialization = {});
void destroyComputeProgram(const Context& ctx, ComputeProgram& program);

VkShaderModule createShaderModule(const Context& ctx, std::span<const uint32_t> spirv, std::string& error);

// Binds the program and its descriptor sets (from set 0), pushes constants and
// dispatches enough groups to cover `threads`. Push constants whose size is not
// the program's are a programming error, not a runtime one: the process stops
// with both sizes named, in every build.
void dispatch(const Context& ctx, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* pushConstants,
              uint32_t pushConstantSize);

// Binds the program and its sets and dispatches no workgroups: a driver that
// compiles at first dispatch (lavapipe) compiles here (gi::vk::warmUp).
inline void warmUp(const Context& ctx, VkCommandBuffer cmd, const ComputeProgram& program,
                   std::span<const VkDescriptorSet> sets) {
  gi::vk::warmUp(ctx.vk, cmd, program, sets);
}

template <typename T>
void dispatch(const Context& ctx, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const T& pushConstants) {
  dispatch(ctx, cmd, program, sets, threads, &pushConstants, sizeof(T));
}

}  // namespace engine
