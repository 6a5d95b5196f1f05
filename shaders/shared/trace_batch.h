// Interface of trace_batch.comp: traces a list of rays through the one trace
// interface (closest hit and visibility), so the traversal backends can be
// compared with each other and with Embree ray by ray.
#ifndef GI_TRACE_BATCH_H
#define GI_TRACE_BATCH_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST TB_BINDING_RAYS = 0;     // TraceBatchRay[]
GPU_CONST TB_BINDING_RESULTS = 1;  // TraceBatchResult[]
#define TB_GROUP_SIZE 64u

struct TraceBatchRay {
  vec3 origin;
  float tMin;
  vec3 direction;  // need not be unit length: t is in its units
  float tMax;
};
GPU_ASSERT_SIZE(TraceBatchRay, 32);

struct TraceBatchResult {
  float t;           // giTraceClosest: < 0 on a miss
  uint instance;
  uint geometry;
  uint triangle;
  vec2 barycentrics;
  uint visible;      // giTraceVisible over [tMin, tMax]: 1 = nothing in the way
  uint pad0;
};
GPU_ASSERT_SIZE(TraceBatchResult, 32);

struct TraceBatchPush {
  uint count;
  uint pad0;
  uint pad1;
  uint pad2;
};
GPU_ASSERT_SIZE(TraceBatchPush, 16);

GPU_NAMESPACE_END
#endif
