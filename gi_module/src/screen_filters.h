// The screen-space filters as an image operator with its own descriptor set:
// guided filter, cross-bilateral and à-trous. Independent of the scene and of
// the module's frame, so tests drive it on synthetic images.
#pragma once
#include <functional>

#include "compute_program.h"
#include "descriptors.h"
#include "resources.h"
#include "shared/gi_filters.h"

namespace gi {

struct FilterTargets {
  VkImageView guidance, position, input, output, temp, params;  // rgba32f, GENERAL layout (contract in shared/gi_filters.h)
};

// Timestamp/label hooks around each pass; empty functions are allowed.
struct PassHooks {
  std::function<void(VkCommandBuffer, const char*)> begin;
  std::function<void(VkCommandBuffer)> end;
};

struct ScreenFilters {
  engine::Image a[FILTER_STACK], b[FILTER_STACK];  // the guided filter's window statistics (created on its first use)
  engine::DescriptorSet set;
  engine::DescriptorSet aafGlossySets[2];  // AAF's specular terms filtered in place (created when the scene is glossy)
  engine::ComputeProgram moments, box, coefficients, output, bilateral, atrous, aaf, sspsf;
  uint32_t width = 0, height = 0;
  uint64_t memoryBytes = 0;
  bool initialised = false;  // images moved to GENERAL layout
};

struct GuidedFilterParams {
  uint32_t radius = 24;
  float epsilonNormal = 0.01f, epsilonDepth = 0.02f;
  uint32_t guidanceDimensions = 4;
  bool writeCoefficientView = false;  // also write |a|, |b| to the temp image (debug view)
};

// A descriptor set of the filters' layout over other targets: the same
// programs then filter other images (AAF's glossy terms).
engine::DescriptorSet createFilterSet(const engine::Context& ctx, const FilterTargets& targets);
ScreenFilters createScreenFilters(const engine::Context& ctx, uint32_t width, uint32_t height, const FilterTargets& targets);
// Allocates the guided filter's 16 statistics images (16 × width × height × 16 bytes) once.
void ensureGuidedStack(const engine::Context& ctx, ScreenFilters& f);
void destroyScreenFilters(const engine::Context& ctx, ScreenFilters& f);

// Each reads the targets' input and writes their output (and temp as noted),
// ending with a barrier that makes the output visible to compute shaders.
void recordGuidedFilter(VkCommandBuffer cmd, ScreenFilters& f, const GuidedFilterParams& params, const PassHooks& hooks);
void recordBilateral(VkCommandBuffer cmd, ScreenFilters& f, const gpu::BilateralPush& params, const PassHooks& hooks);
void recordAtrous(VkCommandBuffer cmd, ScreenFilters& f, uint32_t iterations, float sigmaColor, float sigmaNormal,
                  float sigmaPosition, const PassHooks& hooks);
// Screen-space path filtering over a window (Meijer §4.1).
void recordSspsf(VkCommandBuffer cmd, ScreenFilters& f, const gpu::SspsfPush& params, const PassHooks& hooks);
// Axis-aligned filtering's separable Gaussian (β per pixel from the params
// image's alpha; pixels with β = 0 neither filter nor contribute); uses temp.
// `targets` is f.set or a set from createFilterSet.
// `term` names the passes (aaf_filter_<term>_rows/_columns). `maxRadius`
// cuts the Gaussian before 3σ (pixels; 0 = never).
void recordAafFilter(VkCommandBuffer cmd, const ScreenFilters& f, VkDescriptorSet targets, const char* term,
                     float cosNormalLimit, float pixelScale, uint32_t maxRadius, const PassHooks& hooks);

}  // namespace gi
