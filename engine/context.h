// Vulkan instance + device + one queue. Headless by default; a windowed caller
// passes the surface extensions GLFW asks for. Requires Vulkan 1.3 with buffer
// device address; ray queries and acceleration structures only for the
// ray-query traversal backend.
#pragma once
#include "vk.h"

#include "gi/vk/device.h"

#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace engine {

// How rays are traced. Auto takes the compute backend (our BVH walked in a
// shader) when the device has no ray queries or is a CPU (lavapipe, where it
// measured 3× faster), otherwise ray queries. Compute creates the device
// without the ray-tracing extensions, as on a GPU that has none.
enum class Traversal { Auto, RayQuery, Compute };
const char* traversalName(Traversal t);  // "auto", "rayquery", "compute"
bool parseTraversal(const std::string& name, Traversal& out);

struct ContextDesc {
  Traversal traversal = Traversal::Auto;        // env GI_TRAVERSAL (auto|rayquery|compute) overrides
  bool validation = false;                      // Khronos validation layer + message counting
  bool synchronizationValidation = false;       // with validation: its synchronization checks too (hazards between
                                                // commands, frames in flight included; VK_EXT_validation_features)
  std::vector<const char*> instanceExtensions;  // e.g. from glfwGetRequiredInstanceExtensions
  bool swapchain = false;                       // enable VK_KHR_swapchain on the device
  std::string deviceNameFilter;                 // substring match; empty = best device (env GI_DEVICE overrides)
  // Bounds-checked shaders: robustBufferAccess, and VK_EXT_robustness2's robustBufferAccess2 and
  // robustImageAccess2 where the device has them, so an index out of range reads zero and its
  // write is dropped instead of reaching other memory (on lavapipe, the host's heap). Off by
  // default, as engines ship; tests compare the two (env GI_ROBUST=1 turns it on).
  bool robustAccess = false;
};

// Counts validation messages so tests can assert there were none.
struct ValidationCounter {
  std::atomic<uint32_t> errors{0};
  std::atomic<uint32_t> warnings{0};
};

struct Context {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  VkQueue queue = VK_NULL_HANDLE;
  VkCommandPool commandPool = VK_NULL_HANDLE;
  // submitAndWait's command buffer and fence, made with the context and reset for each submission rather
  // than allocated and freed each time: Debian 12's validation layer (1.3.239) corrupts the heap when
  // command buffers that carry debug labels are freed and allocated again at frame rate (issue 30;
  // tests/label_stress.cpp reproduces it in seconds; docs/RESULTS.md, "Extremes"). A submission recorded
  // while this one is open (inside another's `record`) gets a command buffer of its own as before.
  VkCommandBuffer oneShot = VK_NULL_HANDLE;
  VkFence oneShotFence = VK_NULL_HANDLE;
  mutable bool oneShotOpen = false;
  VkPhysicalDeviceProperties properties{};
  VkPhysicalDeviceMemoryProperties memoryProperties{};
  VkPhysicalDeviceAccelerationStructurePropertiesKHR accelerationProperties{};
  gi::vk::Device vk;                              // the device through the GI module's Vulkan layer (its passes use it)
  std::unique_ptr<ValidationCounter> validation;  // null when validation is off
  bool debugUtils = false;                        // debug labels available
  bool rayQuery = false;                          // ray-query and acceleration-structure extensions enabled
  bool robustAccess = false;                      // ContextDesc::robustAccess, as the device was made
  Traversal traversal = Traversal::Compute;       // the backend chosen: RayQuery or Compute, never Auto
  uint32_t traversalId() const;                   // gpu::TRAVERSAL_* of `traversal`

  uint32_t validationMessages() const { return validation ? validation->errors + validation->warnings : 0; }
};

// Returns false and fills `error` with one sentence (naming the device and what
// it lacks) when no usable device exists.
bool createContext(const ContextDesc& desc, Context& ctx, std::string& error);
void destroyContext(Context& ctx);
// A device on the context's GPU with the context's own features and extensions
// (the swapchain's only with `swapchain`): the context's, or a second one (second_device.h).
VkResult createEngineDevice(const Context& ctx, bool swapchain, VkDevice& out);

// One-shot command buffer: begin, record with `record`, submit and wait. False (and `error`) when
// any step fails or `error` already holds a sentence; `record` then does not run.
template <typename F>
bool submitAndWait(const Context& ctx, F&& record, std::string& error);
VkCommandBuffer beginOneShot(const Context& ctx, std::string& error);  // null on failure
bool endOneShotAndWait(const Context& ctx, VkCommandBuffer cmd, std::string& error);

template <typename F>
bool submitAndWait(const Context& ctx, F&& record, std::string& error) {
  VkCommandBuffer cmd = beginOneShot(ctx, error);
  if (!cmd) return false;
  record(cmd);
  return endOneShotAndWait(ctx, cmd, error);
}

}  // namespace engine
