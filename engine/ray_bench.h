// The bare ray-query microbenchmark: Mrays/s for camera + diffuse-bounce rays
// with no shading, the ceiling the tracing passes are compared against.
#pragma once
#include "scene_gpu.h"

namespace engine {

struct RayBenchResult {
  uint64_t rays = 0;
  double gpuMs = 0.0;
  double mraysPerSecond() const { return gpuMs > 0.0 ? double(rays) / (gpuMs * 1e3) : 0.0; }
};

// Runs `rounds` timed dispatches (after one untimed warm-up) of
// `pathsPerPixel` two-ray paths per pixel; waits.
RayBenchResult runRayBench(const Context& ctx, const SceneGpu& scene, const gpu::GpuCamera& camera,
                           uint32_t pathsPerPixel = 2, uint32_t rounds = 3);

}  // namespace engine
