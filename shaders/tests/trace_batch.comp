#version 460
// Traces a list of rays (shared/trace_batch.h) with the backend this variant
// was compiled for: the traversal tests compare them ray by ray.
#extension GL_GOOGLE_include_directive : require
#include "trace.glsl"
#include "shared/trace_batch.h"
// The engine's program: its reads are never checked (bounds.glsl).
GI_BOUNDS_UNCHECKED

layout(local_size_x = TB_GROUP_SIZE) in;
layout(set = 1, binding = TB_BINDING_RAYS, scalar) readonly buffer Rays { TraceBatchRay rays[]; };
layout(set = 1, binding = TB_BINDING_RESULTS, scalar) writeonly buffer Results { TraceBatchResult results[]; };
layout(push_constant, scalar) uniform Push { TraceBatchPush pc; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  TraceBatchRay ray = rays[i];
  GiHit hit = giTraceClosest(ray.origin, ray.direction, ray.tMin, ray.tMax);
  TraceBatchResult r;
  r.t = hit.t;
  r.instance = hit.instance;
  r.geometry = hit.geometry;
  r.triangle = hit.triangle;
  r.barycentrics = hit.barycentrics;
  r.visible = giTraceVisible(ray.origin, ray.direction, ray.tMin, ray.tMax) ? 1u : 0u;
  r.pad0 = 0u;
  results[i] = r;
}
