#version 460
// Bare ray throughput: camera rays, then diffuse bounce or shadow rays, with
// no shading, through the same trace interface (trace.glsl) as every pass.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "surface.glsl"
#include "bsdf.glsl"
#include "random.glsl"
#include "camera.glsl"
#include "shared/ray_bench.h"
// The engine's program: its reads are never checked (bounds.glsl).
GI_BOUNDS_UNCHECKED

layout(local_size_x = RB_GROUP_SIZE, local_size_y = RB_GROUP_SIZE) in;
layout(set = 1, binding = RB_BINDING_CAMERA, scalar) uniform CameraBlock { GpuCamera camera; };
layout(set = 1, binding = RB_BINDING_OUTPUT, scalar) buffer Output { float hitDistanceSum[]; };
layout(set = 1, binding = RB_BINDING_COUNTER, scalar) buffer Counter { uint rayCounter; };
layout(push_constant, scalar) uniform Push { RayBenchPush pc; };

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  bool inside = all(lessThan(pixel, uvec2(camera.imageSize)));
  if (inside) {
    float sum = 0.0;
    for (uint i = 0u; i < pc.pathsPerPixel; ++i) {
      GiRng rng = giRngCreate(pixel, i, pc.seed, GI_STREAM_REFERENCE);
      vec3 dir = giCameraRayDirection(camera, vec2(pixel) + giRandom2(rng));
      GiHit hit = giTraceClosest(camera.position, dir, 0.0, GI_FLT_MAX);
      if (hit.t < 0.0) continue;
      sum += hit.t;
      if (pc.kind == RB_KIND_PRIMARY) continue;
      GiSurface s = giSurfaceFromHit(hit, dir);
      vec3 origin = giOffsetRay(s.position, s.geometricNormal);
      if (pc.kind == RB_KIND_DIFFUSE) {
        vec3 bounce = giCosineSample(s.normal, giRandom2(rng));
        GiHit second = giTraceClosest(origin, bounce, 0.0, GI_FLT_MAX);
        sum += max(second.t, 0.0);
      } else {
        vec3 target = mix(sceneConstants().boundsMin, sceneConstants().boundsMax, vec3(giRandom2(rng), giRandom(rng)));
        vec3 toTarget = target - origin;
        float distance = length(toTarget);
        if (distance > 0.0 && giTraceVisible(origin, toTarget / distance, 0.0, distance)) sum += 1.0;
      }
    }
    hitDistanceSum[pixel.y * uint(camera.imageSize.x) + pixel.x] = sum;
  }
  uint rays = subgroupAdd(inside ? giRaysTraced : 0u);
  if (subgroupElect()) atomicAdd(rayCounter, rays);
}
