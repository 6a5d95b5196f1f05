// The engine's calls that tests make many times, with its returned errors (engine/vk.h) turned into
// test failures: a failure is reported with the engine's sentence and the test goes on to fail.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "context.h"
#include "readback.h"
#include "resources.h"

// One-shot commands: recorded by `record`, submitted and waited for.
template <typename F>
void submitOrFail(const engine::Context& c, F&& record) {
  std::string error;
  if (!engine::submitAndWait(c, std::forward<F>(record), error)) ADD_FAILURE() << error;
}

// An image's texels (engine::readbackImage); empty after a failure.
inline std::vector<std::byte> readbackOrFail(const engine::Context& c, const engine::Image& image, VkImageLayout layout,
                                             size_t texelBytes) {
  std::string error;
  std::vector<std::byte> texels = engine::readbackImage(c, image, layout, texelBytes, error);
  if (!error.empty()) ADD_FAILURE() << error;
  return texels;
}

// An output's rgb (engine::readbackRgb); empty after a failure.
inline engine::FloatImage readbackRgbOrFail(const engine::Context& c, VkImage image, VkFormat format, VkExtent2D extent,
                                            float scale = 1.0f, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL) {
  std::string error;
  engine::FloatImage rgb = engine::readbackRgb(c, image, format, extent, error, scale, layout);
  if (!error.empty()) ADD_FAILURE() << error;
  return rgb;
}
