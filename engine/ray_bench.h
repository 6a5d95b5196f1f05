// The bare ray-query microbenchmark: Mrays/s for camera + diffuse-bounce rays
// with no shading, the ceiling the tracing passes are compared against.
#pragma once
#include "scene_gpu.h"
#include "shared/ray_bench.h"

namespace engine {

struct RayBenchResult {
  uint64_t rays = 0;
  double gpuMs = 0.0;
  double mraysPerSecond() const { return gpuMs > 0.0 ? double(rays) / (gpuMs * 1e3) : 0.0; }
};

// Runs `rounds` timed dispatches (after one untimed warm-up) of
// `pathsPerPixel` paths per pixel of `kind` (gpu::RB_KIND_*: the camera ray
// and one more ray) with the `traversal` backend (gpu::TRAVERSAL_*); waits.
// Counts and times every ray of the dispatch. Errors as in vk.h (an empty result and `error`).
RayBenchResult runRayBench(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera, uint32_t kind,
                           uint32_t traversal, std::string& error, uint32_t pathsPerPixel = 2, uint32_t rounds = 3);

// Mrays/s of each kind for one backend: primary from camera-only runs;
// diffuse and shadow from the extra rays over the extra time of their runs.
struct RayRates {
  double primary = 0.0, diffuse = 0.0, shadow = 0.0;
};
RayRates measureRayRates(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera, uint32_t traversal,
                         std::string& error, uint32_t pathsPerPixel = 2, uint32_t rounds = 3);

}  // namespace engine
