// A GLFW window with a Vulkan swapchain, for the engine's windowed mode. The
// instance must be created with windowInstanceExtensions() and the device
// with ContextDesc::swapchain. Frames are presented by blitting an image.
#pragma once
#include <string>
#include <vector>

#include "context.h"
#include "frame_slots.h"

struct GLFWwindow;

namespace engine {

struct Window {
  GLFWwindow* handle = nullptr;
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  VkSwapchainKHR swapchain = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;  // an sRGB format: linear radiance blits encode on write
  VkExtent2D extent{};
  std::vector<VkImage> images;
  std::vector<VkSemaphore> renderDone;  // per swapchain image: the presentation engine holds it until presented
  VkSemaphore imageAcquired[kFramesInFlight] = {};
  FrameSlots slots;                      // kFramesInFlight frames recorded ahead
  uint32_t frames = 0;                   // frames submitted; the slot is frames mod kFramesInFlight
  VkCommandBuffer cmd = VK_NULL_HANDLE;  // this frame's command buffer, between begin and end
};

// Initialises GLFW; false (with a sentence in `error`) when there is no display or no Vulkan support.
bool windowInstanceExtensions(std::vector<const char*>& out, std::string& error);
bool createWindow(const Context& ctx, uint32_t width, uint32_t height, const char* title, Window& window,
                  std::string& error);
void destroyWindow(const Context& ctx, Window& window);
bool windowShouldClose(const Window& window);  // also polls events

// Waits for the frame recorded kFramesInFlight frames ago, acquires an image
// and begins this frame's command buffer. Skipped: the swapchain had to be
// recreated (skip the frame). Failed: `error` says why (vk.h).
enum class WindowFrame { Begun, Skipped, Failed };
WindowFrame beginWindowFrame(const Context& ctx, Window& window, uint32_t& imageIndex, std::string& error);
// Blits `source` (GENERAL layout, any colour format) scaled to the swapchain
// image, submits the frame's command buffer and presents.
bool endWindowFrame(const Context& ctx, Window& window, uint32_t imageIndex, VkImage source, VkExtent2D sourceExtent,
                    std::string& error);

}  // namespace engine
