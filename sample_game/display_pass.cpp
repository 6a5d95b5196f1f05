#include "display_pass.h"

#include <cstring>

#include "display.comp.h"
#include "image_io.h"
#include "readback.h"
#include "shared/display.h"

namespace demo {

DisplayPass createDisplayPass(const engine::Context& ctx, VkExtent2D extent, VkImageView source, std::string& error) {
  DisplayPass d;
  d.extent = extent;
  d.image = engine::createImage(
      ctx, extent, kDisplayFormat,
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, error);
  engine::makeStorageImagesGeneral(ctx, std::span(&d.image, 1), error);
  const engine::Binding bindings[] = {{gpu::DISPLAY_BINDING_SOURCE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                      {gpu::DISPLAY_BINDING_TARGET, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}};
  d.set = engine::createDescriptorSet(ctx, bindings, error);
  if (!error.empty()) {
    destroyDisplayPass(ctx, d);
    return d;
  }
  engine::DescriptorWriter(d.set.set)
      .storageImage(gpu::DISPLAY_BINDING_SOURCE, source)
      .storageImage(gpu::DISPLAY_BINDING_TARGET, d.image.view)
      .write(ctx.vk);
  VkDescriptorSetLayout layouts[] = {d.set.layout};
  d.program = engine::createComputeProgram(ctx, spv_display_comp, layouts, sizeof(gpu::DisplayPush),
                                           {DISPLAY_GROUP_SIZE, DISPLAY_GROUP_SIZE}, error);
  if (!error.empty()) destroyDisplayPass(ctx, d);
  return d;
}

void destroyDisplayPass(const engine::Context& ctx, DisplayPass& d) {
  engine::destroyComputeProgram(ctx, d.program);
  engine::destroyDescriptorSet(ctx, d.set);
  engine::destroyImage(ctx, d.image);
  d = DisplayPass{};
}

void recordDisplay(const engine::Context& ctx, VkCommandBuffer cmd, const DisplayPass& d, float exposure,
                   VkExtent2D sourceExtent) {
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  engine::dispatch(ctx, cmd, d.program, std::span(&d.set.set, 1), {d.extent.width, d.extent.height},
                   gpu::DisplayPush{exposure, 0, {sourceExtent.width, sourceExtent.height}});
}

engine::FloatImage readDisplay(const engine::Context& ctx, const DisplayPass& d, std::string& error) {
  return engine::readbackRgb(ctx, d.image.image, d.image.format, d.extent, error);
}

}  // namespace demo
