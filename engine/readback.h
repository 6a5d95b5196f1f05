// Images read back into float images: the GI module's outputs, display images.
#pragma once
#include "image_io.h"
#include "resources.h"

namespace engine {

// The rgb of an rgba16f or rgba32f image in GENERAL layout (the GI module's
// outputs), divided by `scale`; waits.
FloatImage readbackRgb(const Context& ctx, VkImage image, VkFormat format, VkExtent2D extent, float scale = 1.0f);

}  // namespace engine
