// Images read back into float images: the GI module's outputs, display images.
#pragma once
#include "image_io.h"
#include "resources.h"

namespace engine {

// The rgb of an rgba16f or rgba32f image in `layout` (the GI module's outputs:
// gi::ModuleDesc::outputLayout), divided by `scale`; waits, and leaves it in `layout`.
// Errors as in vk.h: an empty image and `error`.
FloatImage readbackRgb(const Context& ctx, VkImage image, VkFormat format, VkExtent2D extent, std::string& error,
                       float scale = 1.0f, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);

}  // namespace engine
