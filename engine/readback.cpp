#include "readback.h"

#include <glm/gtc/packing.hpp>

#include <cstring>

namespace engine {

FloatImage readbackRgb(const Context& ctx, VkImage image, VkFormat format, VkExtent2D extent, std::string& error,
                       float scale, VkImageLayout layout) {
  Image view;
  view.image = image;
  view.format = format;
  view.extent = extent;
  const bool half = format == VK_FORMAT_R16G16B16A16_SFLOAT, packed = format == VK_FORMAT_B10G11R11_UFLOAT_PACK32;
  const size_t texel = packed ? 4 : half ? 8 : 16;
  std::vector<std::byte> raw = readbackImage(ctx, view, layout, texel, error);
  if (!error.empty()) return FloatImage{};
  FloatImage out(extent.width, extent.height, 3);
  for (size_t p = 0; p < size_t(extent.width) * extent.height; ++p)
    for (size_t c = 0; c < 3; ++c) {
      float v;
      if (packed) {
        uint32_t word;
        std::memcpy(&word, &raw[texel * p], 4);
        v = glm::unpackF2x11_1x10(word)[int(c)];
      } else if (half) {
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
