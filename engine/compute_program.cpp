#include "compute_program.h"

#include <vector>

namespace engine {

VkShaderModule createShaderModule(const Context& ctx, std::span<const uint32_t> spirv) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = spirv.size_bytes();
  info.pCode = spirv.data();
  VkShaderModule module;
  VK_CHECK(vkCreateShaderModule(ctx.device, &info, nullptr, &module));
  return module;
}

ComputeProgram createComputeProgram(const Context& ctx, std::span<const uint32_t> spirv,
                                    std::span<const VkDescriptorSetLayout> setLayouts, uint32_t pushConstantSize,
                                    glm::uvec2 groupSize, std::span<const uint32_t> specialization) {
  ComputeProgram p;
  p.pushConstantSize = pushConstantSize;
  p.groupSize = groupSize;
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantSize};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = uint32_t(setLayouts.size());
  layoutInfo.pSetLayouts = setLayouts.data();
  layoutInfo.pushConstantRangeCount = pushConstantSize > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &p.layout));

  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < specialization.size(); ++i) entries.push_back({i, i * 4u, 4});
  VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), specialization.size_bytes(), specialization.data()};

  VkShaderModule module = createShaderModule(ctx, spirv);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = specialization.empty() ? nullptr : &spec;
  info.layout = p.layout;
  VK_CHECK(vkCreateComputePipelines(ctx.device, VK_NULL_HANDLE, 1, &info, nullptr, &p.pipeline));
  vkDestroyShaderModule(ctx.device, module, nullptr);
  return p;
}

void destroyComputeProgram(const Context& ctx, ComputeProgram& p) {
  if (p.pipeline) vkDestroyPipeline(ctx.device, p.pipeline, nullptr);
  if (p.layout) vkDestroyPipelineLayout(ctx.device, p.layout, nullptr);
  p = ComputeProgram{};
}

void dispatch(VkCommandBuffer cmd, const ComputeProgram& program, std::span<const VkDescriptorSet> sets,
              glm::uvec2 threads, const void* pushConstants, uint32_t pushConstantSize) {
  if (pushConstantSize != program.pushConstantSize) {
    std::fprintf(stderr, "dispatch: push constants are %u bytes but the program expects %u\n", pushConstantSize,
                 program.pushConstantSize);
    std::abort();
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.pipeline);
  if (!sets.empty())
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, program.layout, 0, uint32_t(sets.size()), sets.data(), 0,
                            nullptr);
  if (pushConstantSize > 0)
    vkCmdPushConstants(cmd, program.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantSize, pushConstants);
  glm::uvec2 groups = (threads + program.groupSize - 1u) / program.groupSize;
  if (groups.x > 0 && groups.y > 0) vkCmdDispatch(cmd, groups.x, groups.y, 1);
}

}  // namespace engine
