#version 460
// Reference path tracer: progressive, unbiased for the bounce limit B
// (bounce accounting in path.glsl). One jittered primary ray per sample.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "path.glsl"
#include "camera.glsl"
#include "shared/path_tracer.h"

layout(local_size_x = PT_GROUP_SIZE, local_size_y = PT_GROUP_SIZE) in;

layout(set = 1, binding = PT_BINDING_CAMERA, scalar) uniform CameraBlock { GpuCamera camera; };
layout(set = 1, binding = PT_BINDING_FINAL, rgba32f) uniform image2D accumFinal;
layout(set = 1, binding = PT_BINDING_DIRECT, rgba32f) uniform image2D accumDirect;
layout(set = 1, binding = PT_BINDING_INDIRECT, rgba32f) uniform image2D accumIndirect;
layout(set = 1, binding = PT_BINDING_ALBEDO_DEPTH, rgba32f) uniform image2D accumAlbedoDepth;
layout(set = 1, binding = PT_BINDING_NORMAL, rgba32f) uniform image2D accumNormal;
layout(set = 1, binding = PT_BINDING_RAY_COUNTER, scalar) buffer RayCounter { uint rayCounter; };
layout(push_constant, scalar) uniform Push { PathTracerPush pc; };

struct PathResult {
  vec3 direct;
  vec3 indirect;       // with the first hit's BSDF
  vec3 indirectDemod;  // with the first hit's BSDF replaced by a white Lambertian
  vec3 albedo;
  vec3 normal;
  float depth;
};

PathResult tracePath(uvec2 pixel, uint sampleIndex) {
  PathResult r;
  r.direct = r.indirect = r.indirectDemod = r.albedo = r.normal = vec3(0.0);
  r.depth = 0.0;
  GiRng rng = giRngCreate(pixel, sampleIndex, pc.seed, GI_STREAM_REFERENCE);
  vec2 jitter = pc.pixelJitter != 0u ? giRandom2(rng) : vec2(0.5);
  vec3 direction = giCameraRayDirection(camera, vec2(pixel) + jitter);
  GiHit hit = giTraceClosest(camera.position, direction, 0.0, GI_FLT_MAX);
  if (hit.t < 0.0) {
    r.direct = giSkyRadiance(direction);  // the background
    return r;
  }
  GiSurface s = giSurfaceFromHit(hit, direction);
  r.albedo = s.material.baseColor;
  r.normal = s.normal;
  r.depth = giViewDepth(camera, s.position);
  GiPathSample p = giTracePathFromSurface(s, -direction, pc.maxBounces, pc.russianRouletteStart, rng);
  r.direct = s.material.emission + p.direct;
  r.indirect = p.indirect;
  r.indirectDemod = p.indirectDemod;
  return r;
}

// The first dispatch of a render overwrites the sums, so no clear pass is needed.
#define ACCUMULATE(img, p, value) imageStore(img, p, (pc.firstSample == 0u ? vec4(0.0) : imageLoad(img, p)) + (value))

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  bool inside = all(lessThan(pixel, uvec2(camera.imageSize)));
  if (inside) {
    PathResult sum;
    sum.direct = sum.indirect = sum.indirectDemod = sum.albedo = sum.normal = vec3(0.0);
    sum.depth = 0.0;
    for (uint i = 0u; i < pc.samplesPerDispatch; ++i) {
      PathResult r = tracePath(pixel, pc.firstSample + i);
      sum.direct += r.direct;
      sum.indirect += r.indirect;
      sum.indirectDemod += r.indirectDemod;
      sum.albedo += r.albedo;
      sum.normal += r.normal;
      sum.depth += r.depth;
    }
    ivec2 p = ivec2(pixel);
    ACCUMULATE(accumFinal, p, vec4(sum.direct + sum.indirect, 1.0));
    ACCUMULATE(accumDirect, p, vec4(sum.direct, 1.0));
    ACCUMULATE(accumIndirect, p, vec4(sum.indirectDemod, 1.0));
    ACCUMULATE(accumAlbedoDepth, p, vec4(sum.albedo, sum.depth));
    ACCUMULATE(accumNormal, p, vec4(sum.normal, 1.0));
  }
  uint rays = subgroupAdd(inside ? giRaysTraced : 0u);
  if (subgroupElect()) atomicAdd(rayCounter, rays);
}
