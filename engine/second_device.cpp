#include "second_device.h"

namespace engine {

bool createSecondDevice(const Context& ctx, SecondDevice& out, std::string& error) {
  SecondDevice d;
  if (VkResult r = createEngineDevice(ctx, false, d.device); r != VK_SUCCESS) {
    error = std::string("a second device on '") + ctx.properties.deviceName + "': vkCreateDevice failed (" +
            vkResultName(r) + ")";
    return false;
  }
  // Instance-level lookup is valid for every device function; this device's own pointers come from it.
  const auto getDeviceProcAddr =
      reinterpret_cast<PFN_vkGetDeviceProcAddr>(vkGetInstanceProcAddr(ctx.instance, "vkGetDeviceProcAddr"));
#define ENGINE_SECOND_DEVICE_LOAD(name) d.name = reinterpret_cast<PFN_##name>(getDeviceProcAddr(d.device, #name));
  ENGINE_SECOND_DEVICE_FUNCTIONS(ENGINE_SECOND_DEVICE_LOAD)
#undef ENGINE_SECOND_DEVICE_LOAD
  d.vkGetDeviceQueue(d.device, ctx.queueFamily, 0, &d.queue);
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.queueFamilyIndex = ctx.queueFamily;
  if (VkResult r = d.vkCreateCommandPool(d.device, &poolInfo, nullptr, &d.pool); r != VK_SUCCESS) {
    error = std::string("a second device's command pool: vkCreateCommandPool failed (") + vkResultName(r) + ")";
    d.vkDestroyDevice(d.device, nullptr);
    return false;
  }
  out = d;
  return true;
}

void destroySecondDevice(SecondDevice& d) {
  if (!d.device) return;
  d.vkDeviceWaitIdle(d.device);
  d.vkDestroyCommandPool(d.device, d.pool, nullptr);
  d.vkDestroyDevice(d.device, nullptr);
  d = SecondDevice{};
}

VkCommandBuffer beginSecond(const SecondDevice& d) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = d.pool;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  if (d.vkAllocateCommandBuffers(d.device, &alloc, &cmd) != VK_SUCCESS) return VK_NULL_HANDLE;
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (d.vkBeginCommandBuffer(cmd, &begin) != VK_SUCCESS) return VK_NULL_HANDLE;  // freed with the pool
  return cmd;
}

VkResult submitAndWaitSecond(const SecondDevice& d, VkCommandBuffer cmd) {
  if (VkResult r = d.vkEndCommandBuffer(cmd); r != VK_SUCCESS) return r;
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  if (VkResult r = d.vkCreateFence(d.device, &fenceInfo, nullptr, &fence); r != VK_SUCCESS) return r;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  VkResult r = d.vkQueueSubmit(d.queue, 1, &submit, fence);
  if (r == VK_SUCCESS) r = d.vkWaitForFences(d.device, 1, &fence, VK_TRUE, UINT64_MAX);
  d.vkDestroyFence(d.device, fence, nullptr);
  return r;
}

}  // namespace engine
