// Errors the module and the scene share (module.cpp): a module-internal Vulkan failure (gi::vk::Status)
// as the public gi::Error, "<what>: <call> failed with VK_ERROR_..."; and the engine's device-memory
// callbacks checked (both set, or neither).
#pragma once
#include "gi/gi.h"
#include "gi/vk/status.h"

namespace gi {

Error vulkanError(const char* what, const vk::Status& status);
Error checkDeviceMemory(const DeviceMemoryCallbacks& callbacks, const char* field);

}  // namespace gi
