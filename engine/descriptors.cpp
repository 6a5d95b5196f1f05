#include "descriptors.h"

namespace engine {

DescriptorSet createDescriptorSet(const Context& ctx, std::span<const Binding> bindings, uint32_t variableCount) {
  gi::vk::DescriptorSets sets;
  if (gi::vk::Status s = gi::vk::createDescriptorSets(ctx.vk, bindings, 1, sets, VK_NULL_HANDLE, variableCount)) {
    std::fprintf(stderr, "createDescriptorSet: %s failed with %s\n", s.call, vkResultName(s.result));
    std::abort();
  }
  return {sets.layout, sets.pool, sets[0]};
}

void destroyDescriptorSet(const Context& ctx, DescriptorSet& set) {
  gi::vk::DescriptorSets sets{set.layout, set.pool, {set.set}, true};
  gi::vk::destroyDescriptorSets(ctx.vk, sets);
  set = DescriptorSet{};
}

}  // namespace engine
