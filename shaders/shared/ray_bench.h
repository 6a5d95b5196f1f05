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

struct RayBenchPush {
  uint seed;
  uint pathsPerPixel;  // each: one camera ray, then one cosine-distributed ray from its hit
  uint pad0;
  uint pad1;
};
GPU_ASSERT_SIZE(RayBenchPush, 16);

GPU_NAMESPACE_END
#endif
