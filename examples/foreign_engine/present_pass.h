// The foreign engine's use of the module's output: a fragment shader samples it (in the
// SHADER_READ_ONLY_OPTIMAL layout the engine keeps the outputs in, gi::ModuleDesc::outputLayout) into
// a float target per frame slot, which the engine reads back. The module's contract makes its writes
// visible to this fragment shader and waits for its reads before the next frame writes the output
// again: the pass records no barrier on the output.
#pragma once
#include "gbuffer_pass.h"
#include "vulkan_host.h"

namespace foreign {

inline constexpr VkFormat kPresentFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

struct PresentPass {
  VkExtent2D extent{};
  example::Image targets[kFramesInFlight];  // radiance, W/(sr·m²); read back by copy
  VkSampler sampler = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkDescriptorPool descriptorPool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;  // the output's view: the same image every frame, never rewritten
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
};

// `output`: the module output view to show (gi::outputs(), stable until a resize beyond the largest size).
void createPresentPass(const example::Host& h, VkExtent2D extent, VkImageView output, PresentPass& pass);
void destroyPresentPass(const example::Host& h, PresentPass& pass);
// Draws the output divided by `scale` into the slot's target and copies the target into `readback`
// (rgba32f), readable on the host once `cmd` completes.
void recordPresent(VkCommandBuffer cmd, const PresentPass& pass, uint32_t slot, float scale,
                   const example::Buffer& readback);

}  // namespace foreign
