// The screen-space filters as an image operator with its own descriptor set:
// guided filter, cross-bilateral and à-trous. Independent of the scene and of
// the module's frame, so tests drive it on synthetic images.
#pragma once
#include <functional>

#include "gi/catalogue.h"
#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "shared/gi_filters.h"

namespace gi {

struct FilterTargets {
  VkImageView guidance, position, input, output, temp, params;  // GENERAL layout; rgba32f but `output`
                                                                // (contract in shared/gi_filters.h)
  VkBuffer counters = VK_NULL_HANDLE;  // GiCounters the bounds-checked variant counts into (the module's);
                                       // none: createScreenFilters makes one of its own
};

// A working rgba32f image: light as it is.
inline constexpr gpu::FilterOutputEncoding kPlainOutput{1.0f, 3.402823466e38f};

// Timestamp/label hooks around each pass; empty functions are allowed.
struct PassHooks {
  std::function<void(VkCommandBuffer, Pass)> begin;
  std::function<void(VkCommandBuffer)> end;
};

// The filters' programs and their set layout: built once per module, shared
// by every ScreenFilters (a new render size builds new images and sets only).
struct FilterPrograms {
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  vk::ComputeProgram moments, box, coefficients, output, bilateral, atrous, aaf, sspsf;
};
// One filter program: where FilterPrograms keeps it, its shader's name, SPIR-V, push size and group.
struct FilterProgramInfo {
  vk::ComputeProgram FilterPrograms::*program;
  const char* name;
  std::span<const uint32_t> spirv;
  uint32_t pushSize;
  glm::uvec2 group;
  // It reads the position image (FILTER_BINDING_POSITION); the others take coverage from the guidance's
  // depth, and a method whose programs all do holds no position image.
  bool readsPositions;
};
// gif's four, then bilateral, atrous, aaf_filter, sspsf.
std::span<const FilterProgramInfo> filterProgramCatalogue();
enum class FilterProgram : uint32_t { GifMoments, GifBox, GifCoefficients, GifOutput, Bilateral, Atrous, Aaf, Sspsf };
// The screen filters' programs a method runs (none for a method without screen filters).
std::span<const FilterProgram> filterProgramsOf(Method method);
// Whether any of them reads the position image.
bool filtersReadPositions(Method method);
// The layout alone (programs are then made one by one: createFilterProgram).
vk::Status createFilterLayout(const vk::Device& device, FilterPrograms& programs);
vk::Status createFilterProgram(const vk::Device& device, FilterPrograms& programs, const FilterProgramInfo& info);
// The layout and every program.
vk::Status createFilterPrograms(const vk::Device& device, FilterPrograms& out);
void destroyFilterPrograms(const vk::Device& device, FilterPrograms& programs);

struct ScreenFilters {
  const FilterPrograms* programs = nullptr;
  vk::Image a[FILTER_STACK];                 // the guided filter's window statistics (created on its first use)
  uint32_t guidedSubsample = 1;              // their resolution: one pixel per s×s pixels (ensureGuidedStack)
  vk::DescriptorSets set;                    // a set per target (one, or one per history set the input can be)
  uint32_t inputSet = 0;                     // the set the passes use this frame
  vk::DescriptorSets aafGlossySets;          // two: AAF's specular terms filtered in place (glossy scenes)
  vk::Buffer ownCounters;                    // where the targets named no counters (the filters on their own, in tests)
  uint32_t imageWidth = 0, imageHeight = 0;  // the images' size (the largest render size)
  uint32_t width = 0, height = 0;            // the render rectangle the passes filter, within the images
  uint64_t memoryBytes = 0;
  bool initialised = false;  // images moved to GENERAL layout
};

struct GuidedFilterParams {
  uint32_t radius = 24;  // pixels
  float epsilonNormal = 0.01f, epsilonDepth = 0.02f;
  uint32_t guidanceDimensions = 4;
  bool writeCoefficientView = false;                // also write |a|, |b| to the temp image (debug view)
  gpu::FilterOutputEncoding output = kPlainOutput;  // how the output image holds light
};

// Descriptor sets of the filters' layout, one per target: the same programs
// then filter other images (AAF's glossy terms).
vk::Status createFilterSets(const vk::Device& device, const FilterPrograms& programs,
                            std::span<const FilterTargets> targets, vk::DescriptorSets& out);
// One set per target, all over the same width × height (the module's: its noisy image, or its two
// indirect histories, the passes choosing one a frame through ScreenFilters::inputSet).
vk::Status createScreenFilters(vk::Device& device, const FilterPrograms& programs, uint32_t width, uint32_t height,
                               std::span<const FilterTargets> targets, ScreenFilters& out);
inline vk::Status createScreenFilters(vk::Device& device, const FilterPrograms& programs, uint32_t width,
                                      uint32_t height, const FilterTargets& targets, ScreenFilters& out) {
  return createScreenFilters(device, programs, width, height, std::span(&targets, 1), out);
}
// Allocates the guided filter's FILTER_STACK statistics images (rgba32f, ⌈width/s⌉ × ⌈height/s⌉ of the
// largest render size) once; `subsample` is gif.subsample (sized resources are remade when it changes), and
// the guided filter runs at the resolution the stack was made for.
vk::Status ensureGuidedStack(vk::Device& device, ScreenFilters& f, uint32_t subsample);
void destroyScreenFilters(vk::Device& device, ScreenFilters& f);
// Moves the guided filter's statistics images to GENERAL layout, once (the filters do it on first use).
void recordScreenFiltersFirstUse(const vk::Device& device, VkCommandBuffer cmd, ScreenFilters& f);

// Each reads the targets' input and writes their output (and temp as noted),
// ending with a barrier that makes the output visible to compute shaders.
// The guided filter needs ensureGuidedStack first.
void recordGuidedFilter(const vk::Device& device, VkCommandBuffer cmd, ScreenFilters& f,
                        const GuidedFilterParams& params, const PassHooks& hooks);
void recordBilateral(const vk::Device& device, VkCommandBuffer cmd, ScreenFilters& f, const gpu::BilateralPush& params,
                     const PassHooks& hooks);
void recordAtrous(const vk::Device& device, VkCommandBuffer cmd, ScreenFilters& f,
                  const gpu::FilterOutputEncoding& output, uint32_t iterations, float sigmaColor, float sigmaNormal,
                  float sigmaPosition, const PassHooks& hooks);
// Screen-space path filtering over a window (Meijer §4.1).
void recordSspsf(const vk::Device& device, VkCommandBuffer cmd, ScreenFilters& f, const gpu::SspsfPush& params,
                 const PassHooks& hooks);
// Axis-aligned filtering's separable Gaussian (β per pixel from the params
// image's alpha; pixels with β = 0 neither filter nor contribute); uses temp.
// `targets` is f.set or a set from createFilterSet.
// `rows` and `columns` name its two passes. `maxRadius` cuts the Gaussian
// before 3σ (pixels; 0 = never). `positionScale`: metres per unit of the
// position image (β is in metres).
void recordAafFilter(const vk::Device& device, VkCommandBuffer cmd, const ScreenFilters& f, VkDescriptorSet targets,
                     const gpu::FilterOutputEncoding& output, Pass rows, Pass columns, float cosNormalLimit,
                     float pixelScale, uint32_t maxRadius, float positionScale, const PassHooks& hooks);

}  // namespace gi
