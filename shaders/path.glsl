// The one path-tracing loop, shared by the reference (path_trace.comp) and the
// GI module's passes. It starts at vertex 0 (a primary hit, ray traced or
// reconstructed from the G-buffer) and returns the light leaving it towards
// V, without vertex 0's own emission.
// Bounce accounting: light reflected at vertex k (by NEE there, or by BSDF
// sampling that hits an emitter at vertex k+1) has taken k indirect bounces
// and is kept for k ≤ maxBounces. k = 0 is direct light. Russian roulette
// divides by the survival probability, so it stays unbiased for any limit.
#ifndef GI_PATH_GLSL
#define GI_PATH_GLSL
#include "lights.glsl"

struct GiPathSample {
  vec3 direct;         // bounce 0: NEE at vertex 0 plus BSDF-sampled emitters seen from it
  vec3 indirect;       // bounces 1..maxBounces, with vertex 0's BSDF
  vec3 indirectDemod;  // the same light with vertex 0's BSDF replaced by a white Lambertian
};

GiPathSample giTracePathFromSurface(GiSurface vertex0, vec3 V, uint maxBounces, uint russianRouletteStart, inout GiRng rng) {
  GiPathSample r;
  r.direct = r.indirect = r.indirectDemod = vec3(0.0);
  GiSurface s = vertex0;
  vec3 throughput = vec3(1.0);
  vec3 throughputDemod = vec3(1.0);
  float previousBsdfPdf = 0.0;
  vec3 origin = vec3(0.0), direction = vec3(0.0);
  for (uint depth = 0u;; ++depth) {
    if (depth > 0u) {
      GiHit hit = giTraceClosest(origin, direction, 0.0, GI_FLT_MAX);
      if (hit.t < 0.0) {  // the sky, weighed against its NEE (giPrepareSky)
        if (GI_SCENE_HAS_SKY) {
          vec3 c = giSkyRadiance(direction) * giPowerHeuristic(previousBsdfPdf, giSkyNeePdf(direction));
          if (depth == 1u) r.direct += throughput * c;
          else {
            r.indirect += throughput * c;
            r.indirectDemod += throughputDemod * c;
          }
        }
        break;
      }
      s = giSurfaceFromHit(hit, direction);
      if (s.frontFace && giMaxComponent(s.material.emission) > 0.0) {
        float w = GI_SCENE_HAS_EMISSIVE ? giPowerHeuristic(previousBsdfPdf, giEmissiveNeePdf(s, hit.geometry, origin)) : 1.0;
        vec3 c = s.material.emission * w;
        if (depth == 1u) r.direct += throughput * c;
        else {
          r.indirect += throughput * c;
          r.indirectDemod += throughputDemod * c;
        }
      }
      if (depth > maxBounces) break;
      V = -direction;
    }
    GiBsdf b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
    vec3 Ld = giDirectLight(s, b, V, true, rng);
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
    throughputDemod = depth == 0u ? vec3(max(dot(s.normal, L), 0.0) * GI_INV_PI / pdf) : throughputDemod * weight;
    throughput *= weight;
    if (depth + 1u >= russianRouletteStart) {
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

#endif
