// Draws Dear ImGui's draw lists into a colour image with its own small
// graphics pipeline (dynamic rendering, one font texture). The engine loads
// Vulkan through volk, so ImGui's stock Vulkan backend (which links the
// loader's symbols directly) is not used.
#pragma once
#include "compute_program.h"
#include "descriptors.h"
#include "resources.h"

struct ImDrawData;

namespace demo {

struct OverlayRenderer {
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  engine::DescriptorSet set;
  engine::Image font;
  VkSampler sampler = VK_NULL_HANDLE;
  // Host-visible, grown on demand; one pair per frame in flight (the host
  // writes a frame's pair while the other frame may still read its own).
  engine::Buffer vertices[2], indices[2];
};

// Uploads ImGui's font atlas (call after ImGui::CreateContext) and builds the
// pipeline for `targetFormat`. Errors as in engine/vk.h: an empty renderer and `error`.
OverlayRenderer createOverlayRenderer(const engine::Context& ctx, VkFormat targetFormat, std::string& error);
void destroyOverlayRenderer(const engine::Context& ctx, OverlayRenderer& renderer);

// Draws over `target` (GENERAL layout, COLOR_ATTACHMENT usage; left in GENERAL).
// Uses buffer pair `frameIndex` mod 2: the frame two before must have completed. False (recording
// nothing) when a grown buffer cannot be made.
bool recordOverlay(const engine::Context& ctx, VkCommandBuffer cmd, OverlayRenderer& renderer, uint32_t frameIndex,
                   const ImDrawData& data, VkImage target, VkImageView targetView, VkExtent2D extent,
                   std::string& error);

}  // namespace demo
