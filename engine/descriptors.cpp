#include "descriptors.h"

namespace engine {

DescriptorSet createDescriptorSet(const Context& ctx, std::span<const Binding> bindings, std::string& error,
                                  uint32_t variableCount) {
  if (!error.empty()) return {};
  gi::vk::DescriptorSets sets;
  const gi::vk::Status s = gi::vk::createDescriptorSets(ctx.vk, bindings, 1, sets, VK_NULL_HANDLE, variableCount);
  if (!vkSucceeded(s.result, "a descriptor set", s.call ? s.call : "", error)) return {};
  return {sets.layout, sets.pool, sets[0]};
}

void destroyDescriptorSet(const Context& ctx, DescriptorSet& set) {
  gi::vk::DescriptorSets sets{set.layout, set.pool, {set.set}, true};
  gi::vk::destroyDescriptorSets(ctx.vk, sets);
  set = DescriptorSet{};
}

}  // namespace engine
