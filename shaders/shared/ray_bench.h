// Interface of the bare ray-query microbenchmark (ray_bench.comp): the
// throughput ceiling that the tracing passes are measured against.
#ifndef GI_RAY_BENCH_H
#define GI_RAY_BENCH_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST RB_BINDING_CAMERA = 0;   // uniform GpuCamera
GPU_CONST RB_BINDING_OUTPUT = 1;   // float[] per pixel: Σ hit distances (keeps the rays from being optimised away)
GPU_CONST RB_BINDING_COUNTER = 2;  // uint: rays traced
#define RB_GROUP_SIZE 8u

// What each path traces after its camera ray. Rates per kind come from the
// difference to a camera-rays-only run (engine/ray_bench.cpp).
GPU_CONST RB_KIND_PRIMARY = 0u;  // camera rays only
GPU_CONST RB_KIND_DIFFUSE = 1u;  // + one cosine-distributed ray from the hit (closest hit)
GPU_CONST RB_KIND_SHADOW = 2u;   // + one visibility ray from the hit to a point in the scene bounds (any hit)

struct RayBenchPush {
  uint seed;
  uint pathsPerPixel;  // each: one camera ray, then one ray of `kind` from its hit
  uint kind;           // RB_KIND_*
  uint pad0;
};
GPU_ASSERT_SIZE(RayBenchPush, 16);

GPU_NAMESPACE_END
#endif
