#include "screen_filters.h"

#include <algorithm>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "aaf_filter.comp.h"
#include "atrous.comp.h"
#include "bilateral.comp.h"
#include "gif_box.comp.h"
#include "gif_coefficients.comp.h"
#include "gif_moments.comp.h"
#include "gif_output.comp.h"
#include "shared/gi_frame.h"
#include "sspsf.comp.h"
#include "shared/aaf.h"

namespace gi {
namespace {

// One pass: hooks around a dispatch and the barrier that publishes it. The push constants get the
// render rectangle (every filter push has `size`).
template <typename Push>
void passOn(const vk::Device& d, VkCommandBuffer cmd, VkDescriptorSet set, const ScreenFilters& f,
            const PassHooks& hooks, Pass name, const vk::ComputeProgram& program, glm::uvec2 threads, Push push) {
  push.size = {f.width, f.height};
  if (hooks.begin) hooks.begin(cmd, name);
  vk::dispatch(d, cmd, program, std::span(&set, 1), threads, push);
  vk::computeToComputeBarrier(d, cmd);
  if (hooks.end) hooks.end(cmd);
}

template <typename Push>
void pass(const vk::Device& d, VkCommandBuffer cmd, const ScreenFilters& f, const PassHooks& hooks, Pass name,
          const vk::ComputeProgram& program, glm::uvec2 threads, const Push& push) {
  passOn(d, cmd, f.set[f.inputSet], f, hooks, name, program, threads, push);
}

}  // namespace

void recordScreenFiltersFirstUse(const vk::Device& d, VkCommandBuffer cmd, ScreenFilters& f) {
  if (f.initialised || !f.a[0].image) return;
  for (uint32_t i = 0; i < FILTER_STACK; ++i)
    vk::imageBarrier(d, cmd, f.a[i].image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE,
                     0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  f.initialised = true;
}

const vk::Binding kFilterBindings[] = {
    {gpu::FILTER_BINDING_GUIDANCE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_POSITION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_INPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_A, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, FILTER_STACK},
    {gpu::FILTER_BINDING_TEMP, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_PARAMS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::FILTER_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
};

constexpr glm::uvec2 kTile{FILTER_GROUP_SIZE, FILTER_GROUP_SIZE}, kLine{FILTER_LINE_GROUP, 1};
const FilterProgramInfo kFilterPrograms[] = {
    {&FilterPrograms::moments, "gif_moments", spv_gif_moments_comp, sizeof(gpu::GuidedMomentsPush), kTile, false},
    {&FilterPrograms::box, "gif_box", spv_gif_box_comp, sizeof(gpu::BoxPush), kLine, false},
    {&FilterPrograms::coefficients, "gif_coefficients", spv_gif_coefficients_comp, sizeof(gpu::GuidedCoefficientsPush),
     kTile, false},
    {&FilterPrograms::output, "gif_output", spv_gif_output_comp, sizeof(gpu::GuidedMomentsPush), kTile, false},
    {&FilterPrograms::bilateral, "bilateral", spv_bilateral_comp, sizeof(gpu::BilateralPush), kTile, false},
    {&FilterPrograms::atrous, "atrous", spv_atrous_comp, sizeof(gpu::AtrousPush), kTile, true},
    {&FilterPrograms::aaf, "aaf_filter", spv_aaf_filter_comp, sizeof(gpu::AafFilterPush), kTile, true},
    {&FilterPrograms::sspsf, "sspsf", spv_sspsf_comp, sizeof(gpu::SspsfPush), kTile, true},
};
static_assert(std::size(kFilterPrograms) == size_t(FilterProgram::Sspsf) + 1);

std::span<const FilterProgramInfo> filterProgramCatalogue() { return kFilterPrograms; }

// The screen filters' programs a method runs.
std::span<const FilterProgram> filterProgramsOf(Method method) {
  static constexpr FilterProgram gif[] = {FilterProgram::GifMoments, FilterProgram::GifBox,
                                          FilterProgram::GifCoefficients, FilterProgram::GifOutput};
  static constexpr FilterProgram bilateral[] = {FilterProgram::Bilateral}, atrous[] = {FilterProgram::Atrous},
                                 aaf[] = {FilterProgram::Aaf}, sspsf[] = {FilterProgram::Sspsf};
  switch (method) {
    case Method::Gif: return gif;
    case Method::Bilateral: return bilateral;
    case Method::Atrous: return atrous;
    case Method::Aaf:
    case Method::AafAo: return aaf;
    case Method::Sspsf: return sspsf;
    default: return {};
  }
}

bool filtersReadPositions(Method method) {
  for (FilterProgram f : filterProgramsOf(method))
    if (kFilterPrograms[size_t(f)].readsPositions) return true;
  return false;
}

vk::Status createFilterLayout(const vk::Device& d, FilterPrograms& f) {
  if (!f.layout) GI_TRY(vk::createDescriptorLayout(d, kFilterBindings, f.layout));
  return {};
}

vk::Status createFilterProgram(const vk::Device& d, FilterPrograms& f, const FilterProgramInfo& info) {
  vk::ComputeProgram& p = f.*info.program;
  if (p.pipeline) return {};
  VkDescriptorSetLayout layouts[] = {f.layout};
  return vk::createComputeProgram(d, info.spirv, layouts, info.pushSize, info.group, {}, p);
}

vk::Status createFilterPrograms(const vk::Device& d, FilterPrograms& out) {
  FilterPrograms f;
  auto build = [&]() -> vk::Status {
    GI_TRY(createFilterLayout(d, f));
    for (const FilterProgramInfo& info : kFilterPrograms) GI_TRY(createFilterProgram(d, f, info));
    return {};
  };
  if (vk::Status s = build()) {
    destroyFilterPrograms(d, f);
    return s;
  }
  out = f;
  return {};
}

void destroyFilterPrograms(const vk::Device& d, FilterPrograms& f) {
  for (const FilterProgramInfo& info : kFilterPrograms) vk::destroyComputeProgram(d, f.*info.program);
  if (f.layout) d.fn.vkDestroyDescriptorSetLayout(d.device, f.layout, d.allocator);
  f = FilterPrograms{};
}

vk::Status createFilterSets(const vk::Device& d, const FilterPrograms& programs, std::span<const FilterTargets> targets,
                            vk::DescriptorSets& out) {
  GI_TRY(vk::createDescriptorSets(d, kFilterBindings, uint32_t(targets.size()), out, programs.layout));
  for (size_t i = 0; i < targets.size(); ++i) {
    const FilterTargets& t = targets[i];
    vk::DescriptorWriter(out[i])
        .storageImage(gpu::FILTER_BINDING_GUIDANCE, t.guidance)
        .storageImage(gpu::FILTER_BINDING_POSITION, t.position)
        .storageImage(gpu::FILTER_BINDING_INPUT, t.input)
        .storageImage(gpu::FILTER_BINDING_OUTPUT, t.output)
        .storageImage(gpu::FILTER_BINDING_TEMP, t.temp)
        .storageImage(gpu::FILTER_BINDING_PARAMS, t.params)
        .buffer(gpu::FILTER_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, t.counters, 0, sizeof(gpu::GiCounters))
        .write(d);
  }
  return {};
}

vk::Status createScreenFilters(vk::Device& d, const FilterPrograms& programs, uint32_t width, uint32_t height,
                               std::span<const FilterTargets> t, ScreenFilters& out) {
  ScreenFilters f;
  f.programs = &programs;
  f.width = f.imageWidth = width;
  f.height = f.imageHeight = height;
  std::vector<FilterTargets> targets(t.begin(), t.end());
  // (A prediction's buffers have no handles; the module always names its counters.)
  if (!targets[0].counters && !d.memory.simulate) {
    if (vk::Status s =
            vk::createBuffer(d, sizeof(gpu::GiCounters), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, f.ownCounters)) {
      destroyScreenFilters(d, f);
      return s;
    }
    if (f.ownCounters.memory.mapped)
      std::memset(f.ownCounters.memory.mapped, 0, sizeof(gpu::GiCounters));  // null: a prediction
    for (FilterTargets& target : targets) target.counters = f.ownCounters.buffer;
  }
  if (vk::Status s = createFilterSets(d, programs, targets, f.set)) {
    destroyScreenFilters(d, f);
    return s;
  }
  out = std::move(f);
  return {};
}

vk::Status ensureGuidedStack(vk::Device& d, ScreenFilters& f, uint32_t subsample) {
  if (f.a[0].image) return {};
  f.guidedSubsample = subsample;
  const VkExtent2D size{(f.imageWidth + subsample - 1) / subsample, (f.imageHeight + subsample - 1) / subsample};
  for (vk::Image& img : f.a)
    if (vk::Status s = vk::createImage(d, size, VK_FORMAT_R32G32B32A32_SFLOAT,
                                       VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, img, true)) {
      for (vk::Image& made : f.a) vk::destroyImage(d, made);
      return s;
    }
  for (const vk::Image& img : f.a) f.memoryBytes += img.memory.size;
  for (VkDescriptorSet set : f.set.sets) {
    vk::DescriptorWriter w(set);
    for (uint32_t i = 0; i < FILTER_STACK; ++i) w.storageImage(gpu::FILTER_BINDING_A, f.a[i].view, i);
    w.write(d);
  }
  return {};
}

void destroyScreenFilters(vk::Device& d, ScreenFilters& f) {
  vk::destroyDescriptorSets(d, f.set);
  vk::destroyDescriptorSets(d, f.aafGlossySets);
  for (vk::Image& img : f.a) vk::destroyImage(d, img);
  vk::destroyBuffer(d, f.ownCounters);
  f = ScreenFilters{};
}

void recordGuidedFilter(const vk::Device& d, VkCommandBuffer cmd, ScreenFilters& f, const GuidedFilterParams& p,
                        const PassHooks& hooks) {
  recordScreenFiltersFirstUse(d, cmd, f);
  const uint32_t s = f.guidedSubsample;
  const glm::uvec2 size{f.width, f.height}, stack{(f.width + s - 1) / s, (f.height + s - 1) / s};
  const uint32_t radius = std::max(1u, (p.radius + s / 2) / s);  // in statistics pixels
  const gpu::GuidedMomentsPush dims{.guidanceDimensions = p.guidanceDimensions,
                                    .writeCoefficientView = p.writeCoefficientView ? 1u : 0u,
                                    .encoding = p.output,
                                    .subsample = s};
  auto box = [&](uint32_t vertical, uint32_t images) {
    pass(d, cmd, f, hooks, vertical ? Pass::GifBoxColumns : Pass::GifBoxRows, f.programs->box,
         {vertical ? stack.x : stack.y, 1},
         gpu::BoxPush{.radius = radius, .vertical = vertical, .imageCount = images, .subsample = s});
  };
  // Window statistics: per-pixel products averaged over s×s blocks, then their box means (rows, columns).
  pass(d, cmd, f, hooks, Pass::GifMoments, f.programs->moments, stack, dims);
  box(0, GIF_MOMENT_IMAGES);
  box(1, GIF_MOMENT_IMAGES);
  // Per-window ridge regression, then the mean of the coefficients over the windows covering each pixel.
  pass(d, cmd, f, hooks, Pass::GifCoefficients, f.programs->coefficients, stack,
       gpu::GuidedCoefficientsPush{.epsilonNormal = p.epsilonNormal, .epsilonDepth = p.epsilonDepth, .subsample = s});
  box(0, GIF_COEFF_IMAGES);
  box(1, GIF_COEFF_IMAGES);
  pass(d, cmd, f, hooks, Pass::GifOutput, f.programs->output, size, dims);
}

void recordAafFilter(const vk::Device& d, VkCommandBuffer cmd, const ScreenFilters& f, VkDescriptorSet targets,
                     const gpu::FilterOutputEncoding& output, Pass rows, Pass columns, float cosNormalLimit,
                     float pixelScale, uint32_t maxRadius, float positionScale, const PassHooks& hooks) {
  passOn(d, cmd, targets, f, hooks, rows, f.programs->aaf, {f.width, f.height},
         gpu::AafFilterPush{0, cosNormalLimit, pixelScale, maxRadius, output, positionScale});
  passOn(d, cmd, targets, f, hooks, columns, f.programs->aaf, {f.width, f.height},
         gpu::AafFilterPush{1, cosNormalLimit, pixelScale, maxRadius, output, positionScale});
}

void recordSspsf(const vk::Device& d, VkCommandBuffer cmd, ScreenFilters& f, const gpu::SspsfPush& params,
                 const PassHooks& hooks) {
  pass(d, cmd, f, hooks, Pass::Sspsf, f.programs->sspsf, {f.width, f.height}, params);
}

void recordBilateral(const vk::Device& d, VkCommandBuffer cmd, ScreenFilters& f, const gpu::BilateralPush& params,
                     const PassHooks& hooks) {
  pass(d, cmd, f, hooks, Pass::Bilateral, f.programs->bilateral, {f.width, f.height}, params);
}

void recordAtrous(const vk::Device& d, VkCommandBuffer cmd, ScreenFilters& f, const gpu::FilterOutputEncoding& output,
                  uint32_t iterations, float sigmaColor, float sigmaNormal, float sigmaPosition,
                  const PassHooks& hooks) {
  // Ping-pong between temp and output so the last iteration lands in output.
  uint32_t source = 0;
  for (uint32_t i = 0; i < iterations; ++i) {
    uint32_t destination = (iterations - 1 - i) % 2 == 0 ? 1u : 2u;
    gpu::AtrousPush push{i, source, destination, sigmaColor, sigmaNormal, sigmaPosition, output};
    pass(d, cmd, f, hooks, Pass::Atrous, f.programs->atrous, {f.width, f.height}, push);
    source = destination;
  }
}

}  // namespace gi
