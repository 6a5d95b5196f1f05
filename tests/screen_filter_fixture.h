// The screen filters on synthetic images, for the filter tests (AAF's Gaussian, the guided filter): a
// device through the module's own function table, the filters' programs, and six W×H rgba32f images
// bound as the filters' guidance, position, input, output, temp and parameters (the guided filter's
// moment stack is its test's own: gi::ensureGuidedStack).
#pragma once

#include <cstring>
#include <vector>

#include "gpu_test.h"
#include "module_device.h"
#include "screen_filters.h"

enum FilterImage : int { kGuidance, kPosition, kInput, kOutput, kTemp, kParams, kFilterImages };

template <uint32_t W, uint32_t H>
class ScreenFilterTest : public GpuTest {
 protected:
  engine::Image images[kFilterImages];
  gi::ScreenFilters filters;
  gi::FilterPrograms programs;
  gi::vk::Device dev;

  void SetUp() override {
    dev = openModuleDevice(ctx);
    std::string error;
    for (engine::Image& img : images)
      img = engine::createImage(
          ctx, {W, H}, VK_FORMAT_R32G32B32A32_SFLOAT,
          VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, error);
    ASSERT_EQ(error, "");
    ASSERT_FALSE(gi::createFilterPrograms(dev, programs));
    ASSERT_FALSE(gi::createScreenFilters(dev, programs, W, H,
                                         {images[kGuidance].view, images[kPosition].view, images[kInput].view,
                                          images[kOutput].view, images[kTemp].view, images[kParams].view},
                                         filters));
    const std::vector<float> zero(size_t{W} * H * 4, 0.0f);
    for (engine::Image& img : images) upload(img, zero);
  }
  void TearDown() override {
    gi::destroyScreenFilters(dev, filters);
    gi::destroyFilterPrograms(dev, programs);
    gi::vk::closeDevice(dev);
    for (engine::Image& img : images) engine::destroyImage(ctx, img);
    GpuTest::TearDown();
  }

  // W×H×4 floats into one of the images.
  void upload(FilterImage image, const std::vector<float>& rgba) { upload(images[image], rgba); }
  // The output image's first `channels` channels per pixel, after `record` ran the filter.
  template <typename Record>
  std::vector<float> filterOutput(Record&& record, uint32_t channels) {
    submitOrFail(ctx, record);
    const std::vector<std::byte> raw = readbackOrFail(ctx, images[kOutput], VK_IMAGE_LAYOUT_GENERAL, 16);
    std::vector<float> out(size_t{W} * H * channels);
    for (size_t p = 0; p < size_t(W) * H; ++p) std::memcpy(&out[channels * p], &raw[16 * p], 4 * channels);
    return out;
  }

 private:
  void upload(engine::Image& image, const std::vector<float>& rgba) {
    std::string error;
    if (!engine::uploadImage(ctx, image, rgba.data(), rgba.size() * 4, VK_IMAGE_LAYOUT_GENERAL, error))
      ADD_FAILURE() << error;
  }
};
