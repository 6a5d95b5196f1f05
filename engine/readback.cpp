#include "readback.h"

#include <cstring>

namespace engine {

FloatImage readbackRgb(const Context& ctx, VkImage image, VkFormat format, VkExtent2D extent, float scale,
                       VkImageLayout layout) {
  Image view;
  view.image = image;
  view.format = format;
  view.extent = extent;
  const bool half = format == VK_FORMAT_R16G16B16A16_SFLOAT;
  const size_t texel = half ? 8 : 16;
  std::vector<std::byte> raw = readbackImage(ctx, view, layout, texel);
  FloatImage out(extent.width, extent.height, 3);
  for (size_t p = 0; p < size_t(extent.width) * extent.height; ++p)
    for (size_t c = 0; c < 3; ++c) {
      float v;
      if (half) {
        uint16_t h;
        std::memcpy(&h, &raw[texel * p + 2 * c], 2);
        v = halfToFloat(h);
      } else {
        std::memcpy(&v, &raw[texel * p + 4 * c], 4);
      }
      out.pixels[3 * p + c] = v / scale;
    }
  return out;
}

}  // namespace engine
