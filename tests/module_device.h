// The module's internal device (its own function table over the test
// context's device), for tests that drive the module's passes directly.
#pragma once
#include "context.h"
#include "gi/vk/device.h"

inline gi::vk::Device openModuleDevice(const engine::Context& ctx) {
  gi::vk::Device device;
  gi::vk::Status s = gi::vk::openDevice(vkGetInstanceProcAddr, ctx.instance, ctx.physicalDevice, ctx.device, device);
  if (s) std::fprintf(stderr, "openDevice: %s is missing\n", s.call);
  return device;
}
