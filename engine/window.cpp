#include "window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

#include "resources.h"

// GLFW declares this only when it includes Vulkan headers itself; declare it against volk's types.
extern "C" VkResult glfwCreateWindowSurface(VkInstance, GLFWwindow*, const VkAllocationCallbacks*, VkSurfaceKHR*);

namespace engine {
namespace {

bool createSwapchain(const Context& ctx, Window& w, std::string& error) {
  const char* what = "the window's swapchain";
  VkSurfaceCapabilitiesKHR caps;
  if (!VK_SUCCEEDED(error, what, vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physicalDevice, w.surface, &caps)))
    return false;
  uint32_t formatCount = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, w.surface, &formatCount, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(formatCount);
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, w.surface, &formatCount, formats.data());
  VkSurfaceFormatKHR chosen = formats[0];
  for (const VkSurfaceFormatKHR& f : formats)
    if (f.format == VK_FORMAT_B8G8R8A8_SRGB || f.format == VK_FORMAT_R8G8B8A8_SRGB) chosen = f;
  int fbw = 0, fbh = 0;
  glfwGetFramebufferSize(w.handle, &fbw, &fbh);
  w.extent = caps.currentExtent.width != UINT32_MAX
                 ? caps.currentExtent
                 : VkExtent2D{uint32_t(std::max(fbw, 1)), uint32_t(std::max(fbh, 1))};
  w.format = chosen.format;
  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = w.surface;
  info.minImageCount = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = chosen.format;
  info.imageColorSpace = chosen.colorSpace;
  info.imageExtent = w.extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  info.clipped = VK_TRUE;
  info.oldSwapchain = w.swapchain;
  VkSwapchainKHR created;
  if (!VK_SUCCEEDED(error, what, vkCreateSwapchainKHR(ctx.device, &info, nullptr, &created))) return false;
  if (w.swapchain) vkDestroySwapchainKHR(ctx.device, w.swapchain, nullptr);
  w.swapchain = created;
  uint32_t count = 0;
  vkGetSwapchainImagesKHR(ctx.device, w.swapchain, &count, nullptr);
  w.images.resize(count);
  vkGetSwapchainImagesKHR(ctx.device, w.swapchain, &count, w.images.data());
  for (VkSemaphore s : w.renderDone) vkDestroySemaphore(ctx.device, s, nullptr);  // the device is idle here
  w.renderDone.assign(count, VK_NULL_HANDLE);
  VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  for (VkSemaphore& s : w.renderDone)
    if (!VK_SUCCEEDED(error, what, vkCreateSemaphore(ctx.device, &sem, nullptr, &s))) return false;
  return true;
}

}  // namespace

bool windowInstanceExtensions(std::vector<const char*>& out, std::string& error) {
  if (!glfwInit()) {
    error = "GLFW could not initialise (is DISPLAY set to a running X server?)";
    return false;
  }
  if (!glfwVulkanSupported()) {
    error = "GLFW found no Vulkan loader for windows";
    return false;
  }
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  out.assign(names, names + count);
  return true;
}

bool createWindow(const Context& ctx, uint32_t width, uint32_t height, const char* title, Window& w,
                  std::string& error) {
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  w.handle = glfwCreateWindow(int(width), int(height), title, nullptr, nullptr);
  if (!w.handle) {
    error = "GLFW could not open a window";
    return false;
  }
  if (glfwCreateWindowSurface(ctx.instance, w.handle, nullptr, &w.surface) != VK_SUCCESS) {
    error = "the window has no Vulkan surface";
    return false;
  }
  VkBool32 supported = VK_FALSE;
  vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice, ctx.queueFamily, w.surface, &supported);
  if (!supported) {
    error = std::string("the Vulkan device '") + ctx.properties.deviceName + "' cannot present to this window";
    return false;
  }
  if (!createSwapchain(ctx, w, error)) return false;
  VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  for (VkSemaphore& acquired : w.imageAcquired)
    if (!VK_SUCCEEDED(error, "the window's semaphores", vkCreateSemaphore(ctx.device, &sem, nullptr, &acquired)))
      return false;
  w.slots = createFrameSlots(ctx, error);
  return error.empty();
}

void destroyWindow(const Context& ctx, Window& w) {
  if (ctx.device) vkDeviceWaitIdle(ctx.device);
  destroyFrameSlots(ctx, w.slots);
  for (VkSemaphore acquired : w.imageAcquired)
    if (acquired) vkDestroySemaphore(ctx.device, acquired, nullptr);
  for (VkSemaphore s : w.renderDone)
    if (s) vkDestroySemaphore(ctx.device, s, nullptr);
  if (w.swapchain) vkDestroySwapchainKHR(ctx.device, w.swapchain, nullptr);
  if (w.surface) vkDestroySurfaceKHR(ctx.instance, w.surface, nullptr);
  if (w.handle) glfwDestroyWindow(w.handle);
  glfwTerminate();
  w = Window{};
}

bool windowShouldClose(const Window& w) {
  glfwPollEvents();
  return glfwWindowShouldClose(w.handle);
}

WindowFrame beginWindowFrame(const Context& ctx, Window& w, uint32_t& imageIndex, std::string& error) {
  if (!waitFrameSlot(ctx, w.slots, w.frames, error)) return WindowFrame::Failed;
  VkResult r = vkAcquireNextImageKHR(ctx.device, w.swapchain, UINT64_MAX, w.imageAcquired[w.frames % kFramesInFlight],
                                     VK_NULL_HANDLE, &imageIndex);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) {
    vkDeviceWaitIdle(ctx.device);
    return createSwapchain(ctx, w, error) ? WindowFrame::Skipped : WindowFrame::Failed;
  }
  if (r != VK_SUBOPTIMAL_KHR && !VK_SUCCEEDED(error, "acquiring a swapchain image", r)) return WindowFrame::Failed;
  w.cmd = beginFrameSlot(ctx, w.slots, w.frames, error);
  return w.cmd ? WindowFrame::Begun : WindowFrame::Failed;
}

bool endWindowFrame(const Context& ctx, Window& w, uint32_t imageIndex, VkImage source, VkExtent2D extent,
                    std::string& error) {
  VkImage target = w.images[imageIndex];
  imageBarrier(w.cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  imageBarrier(w.cmd, source, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
               VK_ACCESS_2_TRANSFER_READ_BIT);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int32_t(extent.width), int32_t(extent.height), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[1] = {int32_t(w.extent.width), int32_t(w.extent.height), 1};
  vkCmdBlitImage(w.cmd, source, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                 &blit, VK_FILTER_LINEAR);
  imageBarrier(w.cmd, source, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
               VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
               VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  imageBarrier(w.cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
               VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, 0);
  if (!submitFrameSlot(ctx, w.slots, w.frames, error, w.imageAcquired[w.frames % kFramesInFlight],
                       VK_PIPELINE_STAGE_TRANSFER_BIT, w.renderDone[imageIndex]))
    return false;
  w.frames++;
  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &w.renderDone[imageIndex];
  present.swapchainCount = 1;
  present.pSwapchains = &w.swapchain;
  present.pImageIndices = &imageIndex;
  VkResult r = vkQueuePresentKHR(ctx.queue, &present);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
    vkDeviceWaitIdle(ctx.device);
    return createSwapchain(ctx, w, error);
  }
  return VK_SUCCEEDED(error, "presenting a frame", r);
}

}  // namespace engine
