// The reference path tracer (shaders/engine/path_trace.comp): progressive, seeded,
// unbiased for a bounce limit. Every error figure in the project is measured
// against its converged output.
#pragma once
#include "compute_program.h"
#include "gpu_timer.h"
#include "image_io.h"
#include "scene_gpu.h"

#include "shared/path_tracer.h"

namespace engine {

struct ReferenceSettings {
  uint32_t maxBounces = 4;  // B: indirect bounces (0 = direct light only)
  uint32_t seed = 1;
  bool pixelJitter = true;            // false: rays through pixel centres (for G-buffer comparisons)
  uint32_t russianRouletteStart = 3;  // bounce from which paths may stop early (unbiased)
};

// Accumulated outputs, already divided by the sample count.
struct ReferenceImages {
  FloatImage final, direct, indirect;  // RGB radiance; `indirect` is demodulated
  FloatImage albedo, normal;           // RGB
  FloatImage depth;                    // 1 channel: view-space depth, metres (0 = background)
};

struct PathTracer {
  ComputeProgram program;
  DescriptorSet set;
  Buffer camera;      // host-visible GpuCamera
  Buffer rayCounter;  // host-visible uint
  Image accum[5];     // final, direct, indirect, albedo+depth, normal (rgba32f sums)
  VkExtent2D extent{};
  uint32_t samples = 0;  // samples accumulated so far
};

// Errors as in vk.h (an empty tracer, empty images, and `error`).
PathTracer createPathTracer(const Context& ctx, const SceneGpu& scene, VkExtent2D extent, std::string& error);
void destroyPathTracer(const Context& ctx, PathTracer& pt);

// Records `samples` more samples per pixel (restarting when firstSample == 0).
// Records the path tracer's warm-up (gi::vk::warmUp): its compile, off the timed dispatches.
void warmPathTracer(const Context& ctx, VkCommandBuffer cmd, const PathTracer& pt, const SceneGpu& scene);
void recordPathTrace(const Context& ctx, VkCommandBuffer cmd, PathTracer& pt, const SceneGpu& scene,
                     const gpu::GpuCamera& camera, const ReferenceSettings& settings, uint32_t firstSample,
                     uint32_t samples, GpuTimer* timer);

// Rays traced since the last call (reads and clears the counter; GPU idle).
uint64_t takeRayCount(PathTracer& pt);

ReferenceImages readReferenceImages(const Context& ctx, const PathTracer& pt, std::string& error);

struct ReferenceRun {
  ReferenceImages images;
  double gpuMs = 0.0;  // sum of path-trace pass times (the program was warmed before: no compile in them)
  uint64_t rays = 0;
  double firstDispatchMs =
      0.0;  // wall time of the program's warm-up: its compile, where the driver compiles at first dispatch
  double wallSeconds = 0.0;
};

// Renders `spp` samples in submissions of at most `samplesPerSubmit` (4 is a good default: one
// submission stays short), and reads back. On failure the run's images are empty and `error` says why.
ReferenceRun renderReference(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera,
                             const ReferenceSettings& settings, uint32_t spp, uint32_t samplesPerSubmit,
                             std::string& error);

}  // namespace engine
