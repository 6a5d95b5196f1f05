#include "compute_program.h"

#include <cstdio>
#include <cstdlib>

namespace engine {

VkShaderModule createShaderModule(const Context& ctx, std::span<const uint32_t> spirv, std::string& error) {
  VkShaderModule module = VK_NULL_HANDLE;
  if (!error.empty()) return module;
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = spirv.size_bytes();
  info.pCode = spirv.data();
  VK_SUCCEEDED(error, "a shader module", vkCreateShaderModule(ctx.device, &info, nullptr, &module));
  return module;
}

ComputeProgram createComputeProgram(const Context& ctx, std::span<const uint32_t> spirv,
                                    std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                                    glm::uvec2 groupSize, std::string& error,
                                    std::span<const uint32_t> specialization) {
  ComputeProgram p;
  if (!error.empty()) return p;
  const gi::vk::Status s =
      gi::vk::createComputeProgram(ctx.vk, spirv, setLayouts, pushConstantSize, groupSize, specialization, p);
  if (!vkSucceeded(s.result, "a compute program", s.call ? s.call : "", error)) destroyComputeProgram(ctx, p);
  return p;
}

void destroyComputeProgram(const Context& ctx, ComputeProgram& p) { gi::vk::destroyComputeProgram(ctx.vk, p); }

void dispatch(const Context& ctx, VkCommandBuffer cmd, const ComputeProgram& program,
              std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* pushConstants,
              uint32_t pushConstantSize) {
  if (pushConstantSize != program.pushConstantSize) {
    std::fprintf(stderr, "dispatch: push constants are %u bytes but the program expects %u\n", pushConstantSize,
                 program.pushConstantSize);
    std::abort();
  }
  gi::vk::dispatch(ctx.vk, cmd, program, sets, threads, pushConstants, pushConstantSize);
}

}  // namespace engine
