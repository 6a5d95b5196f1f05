// The demo's display image: the module's linear composite scaled to the
// window size with an exposure, in a format the overlay can blend onto and
// the swapchain blit (or the PNG writer) can encode.
#pragma once
#include "compute_program.h"
#include "descriptors.h"
#include "image_io.h"
#include "resources.h"

namespace demo {

struct DisplayPass {
  engine::Image image;  // rgba16f, GENERAL layout
  VkExtent2D extent{};
  engine::DescriptorSet set;
  engine::ComputeProgram program;
};

inline constexpr VkFormat kDisplayFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// `source` is an rgba32f storage view in GENERAL layout (the module's composite).
// Errors as in engine/vk.h: an empty pass (or image) and `error`.
DisplayPass createDisplayPass(const engine::Context& ctx, VkExtent2D extent, VkImageView source, std::string& error);
void destroyDisplayPass(const engine::Context& ctx, DisplayPass& pass);
// Waits for the module's compute writes, then fills the display image.
// `sourceExtent`: the render rectangle in the composite (the module's render size).
void recordDisplay(const engine::Context& ctx, VkCommandBuffer cmd, const DisplayPass& pass, float exposure,
                   VkExtent2D sourceExtent);
// The display image as linear RGB floats (after the frame has completed).
engine::FloatImage readDisplay(const engine::Context& ctx, const DisplayPass& pass, std::string& error);

}  // namespace demo
