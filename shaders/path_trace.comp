#version 460
// Reference path tracer: progressive, unbiased for the bounce limit B.
// Vertex 0 is the primary hit. Light reflected at vertex k (by NEE, or by
// BSDF sampling that hits an emitter at vertex k+1) has been through k
// indirect bounces, so it is kept for k ≤ B. Russian roulette divides by the
// survival probability, which keeps the estimator unbiased for any B.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lights.glsl"
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
  GiRng rng = giRngCreate(pixel, sampleIndex, pc.seed);
  vec2 jitter = pc.pixelJitter != 0u ? giRandom2(rng) : vec2(0.5);
  vec3 origin = camera.position;
  vec3 direction = giCameraRayDirection(camera, vec2(pixel) + jitter);
  vec3 throughput = vec3(1.0);
  vec3 throughputDemod = vec3(1.0);
  float previousBsdfPdf = 0.0;

  for (uint depth = 0u;; ++depth) {
    GiHit hit = giTraceClosest(origin, direction, 0.0, GI_FLT_MAX);
    if (hit.t < 0.0) break;  // no environment: the background is black
    GiSurface s = giSurfaceFromHit(hit, direction);
    if (depth == 0u) {
      r.albedo = s.material.baseColor;
      r.normal = s.normal;
      r.depth = giViewDepth(camera, s.position);
    }
    // Emission reached by BSDF sampling from vertex depth-1 (bounce depth-1).
    if (s.frontFace && giMaxComponent(s.material.emission) > 0.0) {
      if (depth == 0u) {
        r.direct += s.material.emission;
      } else {
        float w = GI_SCENE_HAS_EMISSIVE ? giPowerHeuristic(previousBsdfPdf, giEmissiveLightPdf(s, hit.geometry, origin)) : 1.0;
        vec3 c = s.material.emission * w;
        if (depth == 1u) r.direct += throughput * c;
        else {
          r.indirect += throughput * c;
          r.indirectDemod += throughputDemod * c;
        }
      }
    }
    if (depth > pc.maxBounces) break;

    vec3 V = -direction;
    GiBsdf b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
    vec3 Ld = giDirectLight(s, b, V, rng);
    if (depth == 0u) r.direct += Ld;
    else {
      r.indirect += throughput * Ld;
      r.indirectDemod += throughputDemod * Ld;
    }

    vec3 L, weight;
    float pdf;
    vec3 u = vec3(giRandom2(rng), giRandom(rng));
    if (!giBsdfSample(b, s.normal, V, u, L, weight, pdf)) break;
    if (dot(L, s.geometricNormal) <= 0.0) break;  // would pass through the surface
    if (depth == 0u) {
      throughputDemod = vec3(max(dot(s.normal, L), 0.0) * GI_INV_PI / pdf);
    } else {
      throughputDemod *= weight;
    }
    throughput *= weight;
    if (depth + 1u >= pc.russianRouletteStart) {
      float survive = clamp(giMaxComponent(throughput), 0.05, 0.95);
      if (giRandom(rng) >= survive) break;
      throughput /= survive;
      throughputDemod /= survive;
    }
    previousBsdfPdf = pdf;
    origin = giOffsetRay(s.position, s.geometricNormal);
    direction = L;
  }
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
