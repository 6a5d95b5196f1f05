// An engine that is not ours, embedding the installed GI package: Vulkan
// through the system loader with prototypes, its own instance and device
// (features from gi/device.h), two frames in flight with a fence each, and
// settings and size changed while frames are in flight. The scene is empty
// (every ray misses) and the G-buffer a camera-facing emissive plane cleared
// each frame, so the known answer is exact: the composite is the emission.
// Exit status 0 only if every check holds and validation (GI_VALIDATION=1)
// reported nothing.
//
//   standalone_host            run, print a summary
#include <vulkan/vulkan.h>  // before gi.h: the engine's own Vulkan header, prototypes and all

#include <gi/device.h>
#include <gi/gi.h>
#include <gi/scene.h>
#include <shared/gbuffer.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <glm/gtc/packing.hpp>  // unpackHalf1x16: the outputs are half floats

namespace {

int failures = 0;
uint32_t validationMessages = 0;

void expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    failures++;
  }
}

#define CHECK(call)                                                                      \
  do {                                                                                   \
    if (VkResult r_ = (call); r_ != VK_SUCCESS) {                                        \
      std::fprintf(stderr, "%s failed with %s\n", #call, gi::resultName(r_));            \
      std::exit(2);                                                                      \
    }                                                                                    \
  } while (0)

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)) {
    validationMessages++;
    std::fprintf(stderr, "[validation] %s\n", data->pMessage);
  }
  return VK_FALSE;
}

struct Host {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  VkQueue queue = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory{};
};

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
};

uint32_t memoryType(const Host& h, uint32_t bits, VkMemoryPropertyFlags flags) {
  for (uint32_t i = 0; i < h.memory.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (h.memory.memoryTypes[i].propertyFlags & flags) == flags) return i;
  std::fprintf(stderr, "no memory type with flags 0x%x\n", flags);
  std::exit(2);
}

// Host-visible buffer filled with `bytes` of `data` (zeros when null).
Buffer makeBuffer(const Host& h, VkDeviceSize size, VkBufferUsageFlags usage, const void* data = nullptr) {
  Buffer b;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  CHECK(vkCreateBuffer(h.device, &info, nullptr, &b.buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(h.device, b.buffer, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      memoryType(h, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  CHECK(vkAllocateMemory(h.device, &alloc, nullptr, &b.memory));
  CHECK(vkBindBufferMemory(h.device, b.buffer, b.memory, 0));
  CHECK(vkMapMemory(h.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
  if (data) std::memcpy(b.mapped, data, size);
  else std::memset(b.mapped, 0, size);
  return b;
}

void destroyBuffer(const Host& h, Buffer& b) {
  vkDestroyBuffer(h.device, b.buffer, nullptr);
  vkFreeMemory(h.device, b.memory, nullptr);
}

Image makeImage(const Host& h, VkFormat format, uint32_t width, uint32_t height) {
  Image img;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  CHECK(vkCreateImage(h.device, &info, nullptr, &img.image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(h.device, img.image, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = memoryType(h, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  CHECK(vkAllocateMemory(h.device, &alloc, nullptr, &img.memory));
  CHECK(vkBindImageMemory(h.device, img.image, img.memory, 0));
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = img.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  CHECK(vkCreateImageView(h.device, &view, nullptr, &img.view));
  return img;
}

void destroyImage(const Host& h, Image& img) {
  vkDestroyImageView(h.device, img.view, nullptr);
  vkDestroyImage(h.device, img.image, nullptr);
  vkFreeMemory(h.device, img.memory, nullptr);
}

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
             VkAccessFlags2 dstAccess) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = src;
  b.srcAccessMask = srcAccess;
  b.dstStageMask = dst;
  b.dstAccessMask = dstAccess;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

// Instance with validation when GI_VALIDATION is set; the first device with
// a compute queue and every feature gi/device.h lists (compute traversal).
Host createHost() {
  Host h;
  const bool validation = std::getenv("GI_VALIDATION") != nullptr;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "gi standalone host";
  app.apiVersion = VK_API_VERSION_1_3;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = validation ? 1 : 0;
  info.ppEnabledLayerNames = layers;
  info.enabledExtensionCount = validation ? 1 : 0;
  info.ppEnabledExtensionNames = extensions;
  CHECK(vkCreateInstance(&info, nullptr, &h.instance));
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    m.pfnUserCallback = onMessage;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkCreateDebugUtilsMessengerEXT"));
    CHECK(create(h.instance, &m, nullptr, &h.messenger));
  }
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(h.instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(h.instance, &count, devices.data());
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.pNext = &f13;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &f12;
    vkGetPhysicalDeviceFeatures2(d, &f2);
    if (gi::firstMissingFeature(f2, false)) continue;
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, props.data());
    for (uint32_t i = 0; i < families && !h.physical; ++i)
      if (props[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        h.physical = d;
        h.queueFamily = i;
      }
    if (h.physical) break;
  }
  if (!h.physical) {
    std::fprintf(stderr, "no Vulkan 1.3 device has the features gi/device.h lists\n");
    std::exit(2);
  }
  vkGetPhysicalDeviceMemoryProperties(h.physical, &h.memory);
  // The engine's feature chain, with what the module needs switched on.
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.pNext = &f13;
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &f12;
  if (const char* missing = gi::enableRequiredFeatures(f2, false)) {
    std::fprintf(stderr, "the feature chain lacks the struct of %s\n", missing);
    std::exit(2);
  }
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = h.queueFamily;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  std::span<const char* const> deviceExtensions = gi::requiredExtensions(false);
  VkDeviceCreateInfo device{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device.pNext = &f2;
  device.queueCreateInfoCount = 1;
  device.pQueueCreateInfos = &queue;
  device.enabledExtensionCount = uint32_t(deviceExtensions.size());
  device.ppEnabledExtensionNames = deviceExtensions.data();
  CHECK(vkCreateDevice(h.physical, &device, nullptr, &h.device));
  vkGetDeviceQueue(h.device, h.queueFamily, 0, &h.queue);
  return h;
}

// An empty scene (no meshes, no lights, black sky), built by the module:
// every ray misses. The upload is recorded into a command buffer of ours.
gi::Scene* createEmptyScene(const Host& h, VkCommandPool pool) {
  gi::SceneCreateDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;
  desc.instance = h.instance;
  desc.physicalDevice = h.physical;
  desc.device = h.device;
  desc.traversal = gpu::TRAVERSAL_COMPUTE;
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd;
  CHECK(vkAllocateCommandBuffers(h.device, &alloc, &cmd));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  CHECK(vkBeginCommandBuffer(cmd, &begin));
  gi::Scene* scene = nullptr;
  if (gi::Error e = gi::createScene(desc, gi::SceneContents{}, cmd, scene)) {
    std::fprintf(stderr, "gi::createScene: %s\n", e.message.c_str());
    std::exit(1);
  }
  CHECK(vkEndCommandBuffer(cmd));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  CHECK(vkQueueSubmit(h.queue, 1, &submit, VK_NULL_HANDLE));
  CHECK(vkQueueWaitIdle(h.queue));
  vkFreeCommandBuffers(h.device, pool, 1, &cmd);
  gi::finishSceneUpload(scene);
  return scene;
}

// A pinhole at the origin looking down −Z (reversed-Z projection, y down).
// At the origin looking down −Z, 1 rad vertical field of view, reversed Z
// with an infinite far plane: plain column-major arrays, [column * 4 + row].
gi::CameraDesc camera(uint32_t width, uint32_t height) {
  gi::CameraDesc c{};
  for (int i = 0; i < 4; ++i) c.viewFromWorld[i * 5] = 1.0f;
  const float tanHalfFovY = std::tan(0.5f), aspect = float(width) / float(height);
  c.clipFromView[0] = 1.0f / (aspect * tanHalfFovY);
  c.clipFromView[5] = -1.0f / tanHalfFovY;  // y down
  c.clipFromView[11] = -1.0f;               // clip w = −z_view
  c.clipFromView[14] = 0.1f;                // near plane 0.1 m at depth 1
  return c;
}

constexpr float kEmission[3] = {1.0f, 2.0f, 3.0f};
constexpr float kPreExposure = 0.25f;  // the outputs hold light × this (half floats by default)


}  // namespace

int main() {
  if (gi::version() != (GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR)) {
    std::fprintf(stderr, "gi.h and the gi library linked differ in version\n");
    return 1;
  }
  Host h = createHost();
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = h.queueFamily;
  VkCommandPool pool;
  CHECK(vkCreateCommandPool(h.device, &poolInfo, nullptr, &pool));
  gi::Scene* scene = createEmptyScene(h, pool);
  constexpr uint32_t kMaxW = 64, kMaxH = 64, kFramesInFlight = 2, kFrames = 16;
  const VkFormat formats[gpu::GBUFFER_COLOR_COUNT] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM,
                                                      VK_FORMAT_R8G8_UNORM,          VK_FORMAT_R32G32B32A32_SFLOAT,
                                                      VK_FORMAT_R16G16_SFLOAT,       VK_FORMAT_R32_SFLOAT};
  // The G-buffer: what a plane one metre wide per metre of depth, 2 m away and facing the camera, writes.
  const VkClearColorValue clears[gpu::GBUFFER_COLOR_COUNT] = {
      {.float32 = {0, 0, 1, 1}}, {.float32 = {0.5f, 0.5f, 0.5f, 0}}, {.float32 = {1, 0, 0, 0}},
      {.float32 = {kEmission[0], kEmission[1], kEmission[2], 0}}, {.float32 = {0, 0, 0, 0}}, {.float32 = {2, 0, 0, 0}}};
  Image gbuffer[gpu::GBUFFER_COLOR_COUNT];
  for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i) gbuffer[i] = makeImage(h, formats[i], kMaxW, kMaxH);
  const gi::GBufferViews views{gbuffer[gpu::GBUFFER_NORMAL].view,   gbuffer[gpu::GBUFFER_ALBEDO].view,
                               gbuffer[gpu::GBUFFER_MATERIAL].view, gbuffer[gpu::GBUFFER_EMISSION].view,
                               gbuffer[gpu::GBUFFER_MOTION].view,   gbuffer[gpu::GBUFFER_VIEWZ].view};  // depth: linear view Z

  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;  // the loader's: the module loads its own table through it
  desc.instance = h.instance;
  desc.physicalDevice = h.physical;
  desc.device = h.device;
  desc.width = kMaxW;
  desc.height = kMaxH;
  desc.maxWidth = kMaxW;
  desc.maxHeight = kMaxH;
  desc.framesInFlight = kFramesInFlight;
  desc.scene = gi::sceneDesc(scene);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  gi::Module* module = nullptr;

  // Out of memory is an error, not an abort: a budget below what hpsf needs
  // (its three 64×64 rgba32f outputs alone are 192 KiB).
  desc.memoryBudgetBytes = 128 << 10;
  gi::Error oom = gi::create(desc, settings, module);
  expect(oom.code == gi::ErrorCode::VulkanCall && oom.result == VK_ERROR_OUT_OF_DEVICE_MEMORY && !module,
         "create under a 128 KiB budget fails with VK_ERROR_OUT_OF_DEVICE_MEMORY");
  std::printf("under a 128 KiB budget: %s\n", oom.message.c_str());
  gi::destroy(module);  // null unless the check above failed
  module = nullptr;
  desc.memoryBudgetBytes = 0;
  if (gi::Error e = gi::create(desc, settings, module)) {
    std::fprintf(stderr, "gi::create: %s\n", e.message.c_str());
    return 1;
  }

  VkCommandBuffer cmds[kFramesInFlight];
  VkCommandBufferAllocateInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmdInfo.commandPool = pool;
  cmdInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cmdInfo.commandBufferCount = kFramesInFlight;
  CHECK(vkAllocateCommandBuffers(h.device, &cmdInfo, cmds));
  VkFence fences[kFramesInFlight];
  for (VkFence& f : fences) {
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    CHECK(vkCreateFence(h.device, &fenceInfo, nullptr, &f));
  }

  uint32_t width = kMaxW, height = kMaxH;
  uint64_t rays = 0;
  for (uint32_t frame = 0; frame < kFrames; ++frame) {
    const uint32_t slot = frame % kFramesInFlight;
    CHECK(vkWaitForFences(h.device, 1, &fences[slot], VK_TRUE, UINT64_MAX));
    if (frame >= kFramesInFlight) {
      gi::FrameStats st;
      expect(gi::frameStats(module, frame - kFramesInFlight, st) && st.frameIndex == frame - kFramesInFlight,
             "the stats of the frame whose fence signalled are ready");
      rays += st.raysTraced;
    }
    // Changes while the previous frame is still in flight: no idle GPU needed.
    if (frame == 6) {
      settings.method = gi::Method::Gif;
      if (gi::Error e = gi::setSettings(module, settings)) std::fprintf(stderr, "%s\n", e.message.c_str()), failures++;
    }
    if (frame == 10) {
      width = 48;
      height = 40;
      if (gi::Error e = gi::resize(module, width, height)) std::fprintf(stderr, "%s\n", e.message.c_str()), failures++;
    }
    CHECK(vkResetFences(h.device, 1, &fences[slot]));
    VkCommandBuffer cmd = cmds[slot];
    CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    CHECK(vkBeginCommandBuffer(cmd, &begin));
    // "Raster" the G-buffer: clear it (after the last frame's GI passes read it).
    VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (uint32_t i = 0; i < gpu::GBUFFER_COLOR_COUNT; ++i) {
      VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
      b.srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
      b.dstStageMask = VK_PIPELINE_STAGE_2_CLEAR_BIT;
      b.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
      b.oldLayout = frame == 0 ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_GENERAL;
      b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
      b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      b.image = gbuffer[i].image;
      b.subresourceRange = all;
      VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
      dep.imageMemoryBarrierCount = 1;
      dep.pImageMemoryBarriers = &b;
      vkCmdPipelineBarrier2(cmd, &dep);
      vkCmdClearColorImage(cmd, gbuffer[i].image, VK_IMAGE_LAYOUT_GENERAL, &clears[i], 1, &all);
    }
    barrier(cmd, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
            VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    const gi::CameraDesc cam = camera(width, height);
    gi::FrameInputs inputs{views, cam, cam, frame};
    inputs.preExposure = kPreExposure;
    if (gi::Error e = gi::recordFrame(module, cmd, inputs)) {
      std::fprintf(stderr, "%s\n", e.message.c_str());
      return 1;
    }
    CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    CHECK(vkQueueSubmit(h.queue, 1, &submit, fences[slot]));
  }
  CHECK(vkDeviceWaitIdle(h.device));
  gi::FrameStats last;
  expect(gi::frameStats(module, kFrames - 1, last), "the last frame's stats once the device is idle");
  rays += last.raysTraced;
  expect(rays > 0, "the plane's pixels traced paths");

  // The known answer: every ray misses and there are no lights, so the composite is the emission.
  expect(gi::outputs(module).format == VK_FORMAT_R16G16B16A16_SFLOAT, "half-float outputs by default");
  Buffer readback = makeBuffer(h, VkDeviceSize(width) * height * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  VkCommandBuffer cmd = cmds[0];
  CHECK(vkResetCommandBuffer(cmd, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  CHECK(vkBeginCommandBuffer(cmd, &begin));
  barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
          VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {width, height, 1};
  vkCmdCopyImageToBuffer(cmd, gi::outputs(module).composite, VK_IMAGE_LAYOUT_GENERAL, readback.buffer, 1, &region);
  barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
          VK_ACCESS_2_HOST_READ_BIT);
  CHECK(vkEndCommandBuffer(cmd));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  CHECK(vkQueueSubmit(h.queue, 1, &submit, VK_NULL_HANDLE));
  CHECK(vkQueueWaitIdle(h.queue));
  const uint16_t* texels = static_cast<const uint16_t*>(readback.mapped);
  double worst = 0.0;  // relative
  for (size_t p = 0; p < size_t(width) * height; ++p)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, double(std::fabs(glm::unpackHalf1x16(texels[4 * p + c]) / kPreExposure - kEmission[c]) / kEmission[c]));
  expect(worst < 1e-3, "the composite equals the emission (to half-float rounding, pre-exposure divided out)");
  std::printf("%u frames, %u in flight, hpsf then gif, %ux%u then %ux%u: %llu rays, composite within %.2g (relative) of the "
              "emission, %.1f MiB in %u device allocations, %u validation messages\n",
              kFrames, kFramesInFlight, kMaxW, kMaxH, width, height, (unsigned long long)rays, worst,
              double(last.memoryBytes) / 1048576.0, last.deviceAllocations, validationMessages);

  destroyBuffer(h, readback);
  gi::destroy(module);
  for (VkFence f : fences) vkDestroyFence(h.device, f, nullptr);
  vkDestroyCommandPool(h.device, pool, nullptr);
  for (Image& img : gbuffer) destroyImage(h, img);
  gi::destroyScene(scene);
  vkDestroyDevice(h.device, nullptr);
  if (h.messenger) {
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroyMessenger(h.instance, h.messenger, nullptr);
  }
  vkDestroyInstance(h.instance, nullptr);
  if (validationMessages > 0) std::fprintf(stderr, "FAILED: %u validation messages\n", validationMessages);
  return failures == 0 && validationMessages == 0 ? 0 : 1;
}
