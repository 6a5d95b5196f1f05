#include "screen_filters.h"

#include <cstdint>
#include <string>

#include "aaf_filter.comp.h"
#include "atrous.comp.h"
#include "bilateral.comp.h"
#include "gif_box.comp.h"
#include "gif_coefficients.comp.h"
#include "gif_moments.comp.h"
#include "gif_output.comp.h"
#include "sspsf.comp.h"
#include "shared/aaf.h"

namespace gi {
namespace {

void publish(VkCommandBuffer cmd) {
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

// One pass: hooks around a dispatch and the barrier that publishes it.
template <typename Push>
void passOn(VkCommandBuffer cmd, VkDescriptorSet set, const PassHooks& hooks, const char* name,
            const engine::ComputeProgram& program, glm::uvec2 threads, const Push& push) {
  if (hooks.begin) hooks.begin(cmd, name);
  engine::dispatch(cmd, program, std::span(&set, 1), threads, push);
  publish(cmd);
  if (hooks.end) hooks.end(cmd);
}

template <typename Push>
void pass(VkCommandBuffer cmd, const ScreenFilters& f, const PassHooks& hooks, const char* name,
          const engine::ComputeProgram& program, glm::uvec2 threads, const Push& push) {
  passOn(cmd, f.set.set, hooks, name, program, threads, push);
}

void ensureInitialised(VkCommandBuffer cmd, ScreenFilters& f) {
  if (f.initialised || !f.a[0].image) return;
  for (uint32_t i = 0; i < FILTER_STACK; ++i)
    for (engine::Image* img : {&f.a[i], &f.b[i]})
      engine::imageBarrier(cmd, img->image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, 0,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  f.initialised = true;
}

}  // namespace

engine::DescriptorSet createFilterSet(const engine::Context& ctx, const FilterTargets& t) {
  const engine::Binding bindings[] = {
      {gpu::FILTER_BINDING_GUIDANCE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::FILTER_BINDING_POSITION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::FILTER_BINDING_INPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::FILTER_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::FILTER_BINDING_A, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, FILTER_STACK},
      {gpu::FILTER_BINDING_B, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, FILTER_STACK},
      {gpu::FILTER_BINDING_TEMP, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::FILTER_BINDING_PARAMS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
  };
  engine::DescriptorSet set = engine::createDescriptorSet(ctx, bindings);
  engine::DescriptorWriter(set.set)
      .storageImage(gpu::FILTER_BINDING_GUIDANCE, t.guidance)
      .storageImage(gpu::FILTER_BINDING_POSITION, t.position)
      .storageImage(gpu::FILTER_BINDING_INPUT, t.input)
      .storageImage(gpu::FILTER_BINDING_OUTPUT, t.output)
      .storageImage(gpu::FILTER_BINDING_TEMP, t.temp)
      .storageImage(gpu::FILTER_BINDING_PARAMS, t.params)
      .write(ctx);
  return set;
}

ScreenFilters createScreenFilters(const engine::Context& ctx, uint32_t width, uint32_t height, const FilterTargets& t) {
  ScreenFilters f;
  f.width = width;
  f.height = height;
  f.set = createFilterSet(ctx, t);
  VkDescriptorSetLayout layouts[] = {f.set.layout};
  const glm::uvec2 tile{FILTER_GROUP_SIZE, FILTER_GROUP_SIZE}, line{FILTER_LINE_GROUP, 1};
  f.moments = engine::createComputeProgram(ctx, spv_gif_moments_comp, layouts, sizeof(gpu::GuidedMomentsPush), tile);
  f.box = engine::createComputeProgram(ctx, spv_gif_box_comp, layouts, sizeof(gpu::BoxPush), line);
  f.coefficients = engine::createComputeProgram(ctx, spv_gif_coefficients_comp, layouts, sizeof(gpu::GuidedCoefficientsPush), tile);
  f.output = engine::createComputeProgram(ctx, spv_gif_output_comp, layouts, sizeof(gpu::GuidedMomentsPush), tile);
  f.bilateral = engine::createComputeProgram(ctx, spv_bilateral_comp, layouts, sizeof(gpu::BilateralPush), tile);
  f.atrous = engine::createComputeProgram(ctx, spv_atrous_comp, layouts, sizeof(gpu::AtrousPush), tile);
  f.aaf = engine::createComputeProgram(ctx, spv_aaf_filter_comp, layouts, sizeof(gpu::AafFilterPush), tile);
  f.sspsf = engine::createComputeProgram(ctx, spv_sspsf_comp, layouts, sizeof(gpu::SspsfPush), tile);
  return f;
}

void ensureGuidedStack(const engine::Context& ctx, ScreenFilters& f) {
  if (f.a[0].image) return;
  engine::DescriptorWriter w(f.set.set);
  for (uint32_t i = 0; i < FILTER_STACK; ++i) {
    for (engine::Image* img : {&f.a[i], &f.b[i]}) {
      *img = engine::createImage(ctx, {f.width, f.height}, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT);
      f.memoryBytes += img->allocationSize;
    }
    w.storageImage(gpu::FILTER_BINDING_A, f.a[i].view, i);
    w.storageImage(gpu::FILTER_BINDING_B, f.b[i].view, i);
  }
  w.write(ctx);
}

void destroyScreenFilters(const engine::Context& ctx, ScreenFilters& f) {
  for (engine::ComputeProgram* p : {&f.moments, &f.box, &f.coefficients, &f.output, &f.bilateral, &f.atrous, &f.aaf, &f.sspsf})
    engine::destroyComputeProgram(ctx, *p);
  engine::destroyDescriptorSet(ctx, f.set);
  for (engine::DescriptorSet& set : f.aafGlossySets)
    if (set.set) engine::destroyDescriptorSet(ctx, set);
  for (uint32_t i = 0; i < FILTER_STACK; ++i) {
    engine::destroyImage(ctx, f.a[i]);
    engine::destroyImage(ctx, f.b[i]);
  }
  f = ScreenFilters{};
}

void recordGuidedFilter(VkCommandBuffer cmd, ScreenFilters& f, const GuidedFilterParams& p, const PassHooks& hooks) {
  if (!f.a[0].image) {
    std::fprintf(stderr, "recordGuidedFilter: ensureGuidedStack was not called\n");
    std::abort();
  }
  ensureInitialised(cmd, f);
  const glm::uvec2 size{f.width, f.height};
  const gpu::GuidedMomentsPush dims{p.guidanceDimensions, p.writeCoefficientView ? 1u : 0u, 0, 0};
  // Window statistics: per-pixel products, then their box means (rows, then columns).
  pass(cmd, f, hooks, "gif_moments", f.moments, size, dims);
  pass(cmd, f, hooks, "gif_box_rows", f.box, {f.height, 1}, gpu::BoxPush{p.radius, 0, GIF_MOMENT_IMAGES, 0});
  pass(cmd, f, hooks, "gif_box_columns", f.box, {f.width, 1}, gpu::BoxPush{p.radius, 1, GIF_MOMENT_IMAGES, 0});
  // Per-window ridge regression, then the mean of the coefficients over the windows covering each pixel.
  pass(cmd, f, hooks, "gif_coefficients", f.coefficients, size, gpu::GuidedCoefficientsPush{p.epsilonNormal, p.epsilonDepth, 0, 0});
  pass(cmd, f, hooks, "gif_box_rows", f.box, {f.height, 1}, gpu::BoxPush{p.radius, 0, GIF_COEFF_IMAGES, 0});
  pass(cmd, f, hooks, "gif_box_columns", f.box, {f.width, 1}, gpu::BoxPush{p.radius, 1, GIF_COEFF_IMAGES, 0});
  pass(cmd, f, hooks, "gif_output", f.output, size, dims);
}

void recordAafFilter(VkCommandBuffer cmd, const ScreenFilters& f, VkDescriptorSet targets, const char* term,
                     float cosNormalLimit, float pixelScale, uint32_t maxRadius, const PassHooks& hooks) {
  std::string name = std::string("aaf_filter_") + term;
  passOn(cmd, targets, hooks, (name + "_rows").c_str(), f.aaf, {f.width, f.height},
         gpu::AafFilterPush{0, cosNormalLimit, pixelScale, maxRadius});
  passOn(cmd, targets, hooks, (name + "_columns").c_str(), f.aaf, {f.width, f.height},
         gpu::AafFilterPush{1, cosNormalLimit, pixelScale, maxRadius});
}

void recordSspsf(VkCommandBuffer cmd, ScreenFilters& f, const gpu::SspsfPush& params, const PassHooks& hooks) {
  pass(cmd, f, hooks, "sspsf", f.sspsf, {f.width, f.height}, params);
}

void recordBilateral(VkCommandBuffer cmd, ScreenFilters& f, const gpu::BilateralPush& params, const PassHooks& hooks) {
  pass(cmd, f, hooks, "bilateral", f.bilateral, {f.width, f.height}, params);
}

void recordAtrous(VkCommandBuffer cmd, ScreenFilters& f, uint32_t iterations, float sigmaColor, float sigmaNormal,
                  float sigmaPosition, const PassHooks& hooks) {
  // Ping-pong between temp and output so the last iteration lands in output.
  uint32_t source = 0;
  for (uint32_t i = 0; i < iterations; ++i) {
    uint32_t destination = (iterations - 1 - i) % 2 == 0 ? 1u : 2u;
    gpu::AtrousPush push{i, source, destination, sigmaColor, sigmaNormal, sigmaPosition, 0, 0};
    pass(cmd, f, hooks, "atrous", f.atrous, {f.width, f.height}, push);
    source = destination;
  }
}

}  // namespace gi
