// A module-internal Vulkan failure (gi::vk::Status) as the public gi::Error
// (module.cpp): "<what>: <call> failed with VK_ERROR_...".
#pragma once
#include "gi/gi.h"
#include "gi/vk/status.h"

namespace gi {

Error vulkanError(const char* what, const vk::Status& status);

}  // namespace gi
