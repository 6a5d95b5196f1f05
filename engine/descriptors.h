// The engine's descriptor sets on the GI module's Vulkan layer
// (gi/vk/programs.h): a layout from a binding list, a pool sized for it and
// one set; the module's batching writer. Each pass owns its own set(s).
#pragma once
#include "context.h"

#include <span>
#include <string>

#include "gi/vk/programs.h"

namespace engine {

using Binding = gi::vk::Binding;
using DescriptorWriter = gi::vk::DescriptorWriter;  // .write(ctx.vk)

struct DescriptorSet {
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
};

// Creates a layout (all stages), a pool and one set. `variableCount` is the
// actual size of the variable-count binding, if there is one.
// Errors as in vk.h: an empty set and `error`.
DescriptorSet createDescriptorSet(const Context& ctx, std::span<const Binding> bindings, std::string& error,
                                  uint32_t variableCount = 0);
void destroyDescriptorSet(const Context& ctx, DescriptorSet& set);

}  // namespace engine
