#include "context.h"

#include "gi/gi.h"

#include "gi/device.h"
#include "shared/gpu_scene.h"

#include <algorithm>
#include <cstring>

namespace engine {

const char* vkResultName(VkResult result) { return gi::resultName(result); }

bool vkSucceeded(VkResult result, const char* what, const char* call, std::string& error) {
  if (result == VK_SUCCESS) return true;
  const std::string text = call;
  error = std::string(what) + ": " + text.substr(0, text.find('(')) + " failed with " + vkResultName(result);
  return false;
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* counter = static_cast<ValidationCounter*>(user);
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    counter->errors++;
    std::fprintf(stderr, "[validation error] %s\n", data->pMessage);
  } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    counter->warnings++;
    std::fprintf(stderr, "[validation warning] %s\n", data->pMessage);
  }
  return VK_FALSE;
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> exts(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, exts.data());
  return std::any_of(exts.begin(), exts.end(), [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::vector<std::string> deviceExtensions(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> exts(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, exts.data());
  std::vector<std::string> names;
  for (const auto& e : exts) names.emplace_back(e.extensionName);
  return names;
}

int deviceTypeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

const char* const kTraversalNames[] = {"auto", "rayquery", "compute"};

}  // namespace

const char* traversalName(Traversal t) { return kTraversalNames[int(t)]; }

bool parseTraversal(const std::string& name, Traversal& out) {
  for (int i = 0; i < 3; ++i)
    if (name == kTraversalNames[i]) {
      out = Traversal(i);
      return true;
    }
  return false;
}

uint32_t Context::traversalId() const {
  return traversal == Traversal::RayQuery ? gpu::TRAVERSAL_RAY_QUERY : gpu::TRAVERSAL_COMPUTE;
}

VkResult createEngineDevice(const Context& ctx, bool swapchain, VkDevice& out) {
  VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  vkGetPhysicalDeviceFeatures2(ctx.physicalDevice, &supported);
  // Enable exactly what we use.
  VkPhysicalDeviceRayQueryFeaturesKHR rayQueryOn{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR accelOn{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  accelOn.pNext = &rayQueryOn;
  VkPhysicalDeviceVulkan13Features f13On{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  f13On.dynamicRendering = VK_TRUE;
  f13On.maintenance4 = VK_TRUE;
  f13On.pNext = ctx.rayQuery ? &accelOn : nullptr;
  VkPhysicalDeviceVulkan12Features f12On{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12On.bufferDeviceAddress = VK_TRUE;
  f12On.pNext = &f13On;
  VkPhysicalDeviceFeatures2 f2On{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2On.features.shaderStorageImageReadWithoutFormat = supported.features.shaderStorageImageReadWithoutFormat;
  f2On.pNext = &f12On;
  if (gi::enableRequiredFeatures(f2On, ctx.rayQuery))
    return VK_ERROR_FEATURE_NOT_PRESENT;  // a struct the chain lacks: a bug
  // Bounds-checked access (ContextDesc::robustAccess): robustness2 where the device has it.
  VkPhysicalDeviceRobustness2FeaturesEXT robust2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ROBUSTNESS_2_FEATURES_EXT};
  const std::vector<std::string> have = deviceExtensions(ctx.physicalDevice);
  const bool robustness2 =
      ctx.robustAccess && std::find(have.begin(), have.end(), VK_EXT_ROBUSTNESS_2_EXTENSION_NAME) != have.end();
  if (ctx.robustAccess) {
    f2On.features.robustBufferAccess = supported.features.robustBufferAccess;
    if (robustness2) {
      VkPhysicalDeviceRobustness2FeaturesEXT can{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ROBUSTNESS_2_FEATURES_EXT};
      VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
      query.pNext = &can;
      vkGetPhysicalDeviceFeatures2(ctx.physicalDevice, &query);
      robust2.robustBufferAccess2 = can.robustBufferAccess2;
      robust2.robustImageAccess2 = can.robustImageAccess2;
      robust2.pNext = f2On.pNext;
      f2On.pNext = &robust2;
    }
  }

  const char* deviceExts[std::size(gi::kRayQueryExtensions) + 2];
  uint32_t extensionCount = 0;
  for (const char* ext : gi::requiredExtensions(ctx.rayQuery)) deviceExts[extensionCount++] = ext;
  if (swapchain) deviceExts[extensionCount++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
  if (robustness2) deviceExts[extensionCount++] = VK_EXT_ROBUSTNESS_2_EXTENSION_NAME;
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = ctx.queueFamily;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.pNext = &f2On;
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  deviceInfo.enabledExtensionCount = extensionCount;
  deviceInfo.ppEnabledExtensionNames = deviceExts;
  return vkCreateDevice(ctx.physicalDevice, &deviceInfo, nullptr, &out);
}

namespace {

// The instance, with the validation layer and its message counter when asked for.
bool createInstance(const ContextDesc& desc, Context& ctx, std::string& error) {
  if (volkInitialize() != VK_SUCCESS) {
    error =
        "No Vulkan loader was found (libvulkan.so.1); install libvulkan1 and a Vulkan driver such as "
        "mesa-vulkan-drivers.";
    return false;
  }
  if (volkGetInstanceVersion() < VK_API_VERSION_1_3) {
    error = "The Vulkan loader supports only Vulkan " + std::to_string(VK_API_VERSION_MAJOR(volkGetInstanceVersion())) +
            "." + std::to_string(VK_API_VERSION_MINOR(volkGetInstanceVersion())) + "; the GI module needs Vulkan 1.3.";
    return false;
  }

  std::vector<const char*> layers;
  std::vector<const char*> extensions = desc.instanceExtensions;
  if (desc.validation) {
    if (!hasLayer("VK_LAYER_KHRONOS_validation")) {
      error =
          "Validation was requested but VK_LAYER_KHRONOS_validation is not installed (apt-get install "
          "vulkan-validationlayers).";
      return false;
    }
    layers.push_back("VK_LAYER_KHRONOS_validation");
  }
  ctx.debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (ctx.debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (desc.validation && !ctx.debugUtils) {
    error = "Validation was requested but VK_EXT_debug_utils is unavailable, so its messages could not be counted.";
    return false;
  }

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "gi_module";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instanceInfo.pApplicationInfo = &app;
  instanceInfo.enabledLayerCount = uint32_t(layers.size());
  instanceInfo.ppEnabledLayerNames = layers.data();
  instanceInfo.enabledExtensionCount = uint32_t(extensions.size());
  instanceInfo.ppEnabledExtensionNames = extensions.data();

  VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  if (desc.validation) {
    ctx.validation = std::make_unique<ValidationCounter>();
    messengerInfo.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    messengerInfo.pfnUserCallback = onValidationMessage;
    messengerInfo.pUserData = ctx.validation.get();
    instanceInfo.pNext = &messengerInfo;  // also catches messages from vkCreateInstance itself
  }
  const VkValidationFeatureEnableEXT syncChecks = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  if (desc.validation && desc.synchronizationValidation) {
    extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);  // the validation layer's own
    instanceInfo.enabledExtensionCount = uint32_t(extensions.size());
    instanceInfo.ppEnabledExtensionNames = extensions.data();
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = &syncChecks;
    features.pNext = instanceInfo.pNext;
    instanceInfo.pNext = &features;
  }
  VkResult r = vkCreateInstance(&instanceInfo, nullptr, &ctx.instance);
  if (r != VK_SUCCESS) {
    error = std::string("vkCreateInstance failed (") + vkResultName(r) + "); is a Vulkan 1.3 driver installed?";
    return false;
  }
  volkLoadInstanceOnly(ctx.instance);
  if (desc.validation) {
    if (VkResult made = vkCreateDebugUtilsMessengerEXT(ctx.instance, &messengerInfo, nullptr, &ctx.messenger);
        made != VK_SUCCESS) {
      error = std::string("vkCreateDebugUtilsMessengerEXT failed (") + vkResultName(made) +
              "): validation messages could not be counted";
      return false;
    }
  }
  return true;
}

// The best-ranked device (discrete first, CPU last) that matches the name filter and has what the traversal
// needs; the traversal resolved for it (Auto: ray queries where the device has them, unless it is a CPU device).
bool pickPhysicalDevice(const ContextDesc& desc, Context& ctx, std::string& error) {
  uint32_t deviceCount = 0;
  vkEnumeratePhysicalDevices(ctx.instance, &deviceCount, nullptr);
  std::vector<VkPhysicalDevice> devices(deviceCount);
  vkEnumeratePhysicalDevices(ctx.instance, &deviceCount, devices.data());
  std::string filter = desc.deviceNameFilter;
  if (const char* env = std::getenv("GI_DEVICE")) filter = env;
  Traversal traversal = desc.traversal;
  if (const char* env = std::getenv("GI_TRAVERSAL")) {
    if (!parseTraversal(env, traversal)) {
      error = std::string("GI_TRAVERSAL='") + env + "' is not one of auto, rayquery, compute.";
      return false;
    }
  }
  const bool needRayQuery = traversal == Traversal::RayQuery;
  VkPhysicalDevice best = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties bestProps{};
  std::string bestMissing;
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(d, &props);
    if (!filter.empty() && std::string(props.deviceName).find(filter) == std::string::npos) continue;
    std::vector<std::string> have = deviceExtensions(d);
    std::string missing;
    if (props.apiVersion < VK_API_VERSION_1_3) missing = "Vulkan 1.3";
    if (needRayQuery)
      for (const char* ext : gi::kRayQueryExtensions)
        if (missing.empty() && std::find(have.begin(), have.end(), ext) == have.end()) missing = ext;
    if (desc.swapchain && missing.empty() &&
        std::find(have.begin(), have.end(), VK_KHR_SWAPCHAIN_EXTENSION_NAME) == have.end())
      missing = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    // A usable device always beats an unusable one; among equals, the better type wins.
    bool better = best == VK_NULL_HANDLE || (missing.empty() && !bestMissing.empty()) ||
                  (missing.empty() == bestMissing.empty() &&
                   deviceTypeRank(props.deviceType) < deviceTypeRank(bestProps.deviceType));
    if (better) {
      best = d;
      bestProps = props;
      bestMissing = missing;
    }
  }
  if (best == VK_NULL_HANDLE) {
    error =
        filter.empty() ? "No Vulkan device was found." : "No Vulkan device matches the name filter '" + filter + "'.";
    return false;
  }
  if (!bestMissing.empty()) {
    error = std::string("The Vulkan device '") + bestProps.deviceName + "' does not support " + bestMissing +
            (needRayQuery ? ", which the ray-query traversal needs (use --traversal compute, or on Debian 12 install "
                            "mesa-vulkan-drivers from bookworm-backports)."
                          : ", which the GI module needs.");
    return false;
  }
  // Auto: ray queries where the device has them, unless it is a CPU device,
  // where our compute traversal measured faster (docs/RESULTS.md).
  std::vector<std::string> bestExtensions = deviceExtensions(best);
  bool deviceHasRayQuery = true;
  for (const char* ext : gi::kRayQueryExtensions)
    deviceHasRayQuery &= std::find(bestExtensions.begin(), bestExtensions.end(), ext) != bestExtensions.end();
  // Auto keeps the extensions on where the device has them, so the ray bench
  // can compare both backends; an explicit Compute creates the device without them.
  ctx.rayQuery = traversal == Traversal::RayQuery || (traversal == Traversal::Auto && deviceHasRayQuery);
  if (traversal == Traversal::Auto)
    traversal = deviceHasRayQuery && bestProps.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU ? Traversal::RayQuery
                                                                                         : Traversal::Compute;
  ctx.traversal = traversal;
  ctx.robustAccess = desc.robustAccess;
  if (const char* env = std::getenv("GI_ROBUST")) ctx.robustAccess = std::string(env) == "1";
  ctx.physicalDevice = best;
  ctx.properties = bestProps;
  vkGetPhysicalDeviceMemoryProperties(best, &ctx.memoryProperties);
  return true;
}

// Feature chain: check what we need before enabling it. The GI module's
// needs come from its public catalogue (gi/device.h); the engine adds its own.
bool checkDeviceFeatures(const Context& ctx, std::string& error) {
  const VkPhysicalDevice best = ctx.physicalDevice;
  const VkPhysicalDeviceProperties& bestProps = ctx.properties;
  VkPhysicalDeviceRayQueryFeaturesKHR rayQuery{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR accel{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  accel.pNext = &rayQuery;
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  f13.pNext = ctx.rayQuery ? &accel : nullptr;
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.pNext = &f13;
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &f12;
  vkGetPhysicalDeviceFeatures2(best, &f2);
  const char* missing = gi::firstMissingFeature(f2, ctx.rayQuery);
  struct Need {
    VkBool32 have;
    const char* name;
  };
  const Need engineNeeds[] = {
      {f12.bufferDeviceAddress, "bufferDeviceAddress"},  // scene buffers carry device addresses
      {f13.dynamicRendering, "dynamicRendering"},        // the G-buffer pass
      {f13.maintenance4, "maintenance4"},
  };
  for (const Need& n : engineNeeds)
    if (!missing && !n.have) missing = n.name;
  if (missing) {
    error = std::string("The Vulkan device '") + bestProps.deviceName + "' does not support " + missing +
            ", which the GI module or the engine needs.";
    return false;
  }
  return true;
}

// A queue family with graphics, compute and timestamps.
bool pickQueueFamily(Context& ctx, std::string& error) {
  const VkPhysicalDevice best = ctx.physicalDevice;
  uint32_t familyCount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(best, &familyCount, nullptr);
  std::vector<VkQueueFamilyProperties> families(familyCount);
  vkGetPhysicalDeviceQueueFamilyProperties(best, &familyCount, families.data());
  ctx.queueFamily = UINT32_MAX;
  for (uint32_t i = 0; i < familyCount; ++i) {
    VkQueueFlags want = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & want) == want && families[i].timestampValidBits > 0) {
      ctx.queueFamily = i;
      break;
    }
  }
  if (ctx.queueFamily == UINT32_MAX) {
    error = std::string("The Vulkan device '") + ctx.properties.deviceName +
            "' has no queue family with graphics, compute and timestamps.";
    return false;
  }
  return true;
}

}  // namespace

bool createContext(const ContextDesc& desc, Context& ctx, std::string& error) {
  if (!createInstance(desc, ctx, error) || !pickPhysicalDevice(desc, ctx, error) || !checkDeviceFeatures(ctx, error) ||
      !pickQueueFamily(ctx, error))
    return false;
  const VkPhysicalDevice best = ctx.physicalDevice;
  if (VkResult made = createEngineDevice(ctx, desc.swapchain, ctx.device); made != VK_SUCCESS) {
    error = std::string("vkCreateDevice failed on '") + ctx.properties.deviceName + "' (" + vkResultName(made) + ").";
    return false;
  }
  volkLoadDevice(ctx.device);
  vkGetDeviceQueue(ctx.device, ctx.queueFamily, 0, &ctx.queue);
  if (gi::vk::Status s =
          gi::vk::openDevice(vkGetInstanceProcAddr, ctx.instance, ctx.physicalDevice, ctx.device, ctx.vk)) {
    error = std::string("the Vulkan loader returned no ") + s.call + " for '" + ctx.properties.deviceName + "'";
    return false;
  }

  if (ctx.rayQuery) {
    ctx.accelerationProperties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
    VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props2.pNext = &ctx.accelerationProperties;
    vkGetPhysicalDeviceProperties2(best, &props2);
  }

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = ctx.queueFamily;
  if (VkResult made = vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &ctx.commandPool); made != VK_SUCCESS) {
    error =
        std::string("vkCreateCommandPool failed on '") + ctx.properties.deviceName + "' (" + vkResultName(made) + ").";
    return false;
  }
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  const VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  return VK_SUCCEEDED(error, "the one-shot command buffer",
                      vkAllocateCommandBuffers(ctx.device, &alloc, &ctx.oneShot)) &&
         VK_SUCCEEDED(error, "the one-shot fence", vkCreateFence(ctx.device, &fenceInfo, nullptr, &ctx.oneShotFence));
}

void destroyContext(Context& ctx) {
  if (ctx.device) {
    vkDeviceWaitIdle(ctx.device);
    if (ctx.oneShotFence) vkDestroyFence(ctx.device, ctx.oneShotFence, nullptr);
    vkDestroyCommandPool(ctx.device, ctx.commandPool, nullptr);  // and ctx.oneShot with it
    vkDestroyDevice(ctx.device, nullptr);
  }
  if (ctx.messenger) vkDestroyDebugUtilsMessengerEXT(ctx.instance, ctx.messenger, nullptr);
  if (ctx.instance) vkDestroyInstance(ctx.instance, nullptr);
  ctx.device = VK_NULL_HANDLE;
  ctx.messenger = VK_NULL_HANDLE;
  ctx.instance = VK_NULL_HANDLE;
  ctx.oneShot = VK_NULL_HANDLE;
  ctx.oneShotFence = VK_NULL_HANDLE;
}

VkCommandBuffer beginOneShot(const Context& ctx, std::string& error) {
  if (!error.empty()) return VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  const bool reused = ctx.oneShot && !ctx.oneShotOpen;
  if (reused) {
    cmd = ctx.oneShot;  // vkBeginCommandBuffer resets it (the pool allows it)
  } else {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = ctx.commandPool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    if (!VK_SUCCEEDED(error, "one-shot commands", vkAllocateCommandBuffers(ctx.device, &alloc, &cmd)))
      return VK_NULL_HANDLE;
  }
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (!VK_SUCCEEDED(error, "one-shot commands", vkBeginCommandBuffer(cmd, &begin))) {
    if (!reused) vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &cmd);
    return VK_NULL_HANDLE;
  }
  if (reused) ctx.oneShotOpen = true;
  return cmd;
}

bool endOneShotAndWait(const Context& ctx, VkCommandBuffer cmd, std::string& error) {
  const char* what = "one-shot commands";
  const bool reused = cmd == ctx.oneShot;
  VkFence fence = reused ? ctx.oneShotFence : VK_NULL_HANDLE;
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  const bool done = VK_SUCCEEDED(error, what, vkEndCommandBuffer(cmd)) &&
                    (reused ? VK_SUCCEEDED(error, what, vkResetFences(ctx.device, 1, &fence))
                            : VK_SUCCEEDED(error, what, vkCreateFence(ctx.device, &fenceInfo, nullptr, &fence))) &&
                    VK_SUCCEEDED(error, what, vkQueueSubmit(ctx.queue, 1, &submit, fence)) &&
                    VK_SUCCEEDED(error, what, vkWaitForFences(ctx.device, 1, &fence, VK_TRUE, UINT64_MAX));
  // A submission that failed after it was queued (a lost device) still holds the buffer: wait out the queue.
  if (!done) vkQueueWaitIdle(ctx.queue);
  if (reused) {
    ctx.oneShotOpen = false;
    return done;
  }
  if (fence) vkDestroyFence(ctx.device, fence, nullptr);
  vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &cmd);
  return done;
}

}  // namespace engine
