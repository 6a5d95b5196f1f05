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

// The path as a part of a ray task (ray_loop.glsl): giPathNext asks for NEE
// at the vertex, then for the BSDF-sampled continuation; giPathTakeNee and
// giPathTakeHit take their answers. `result` is final once giPathNext says
// GI_STEP_DONE. Random numbers are drawn in the order of a plain loop (NEE,
// the BSDF sample, Russian roulette) from the task's `rng`.
#define GI_PATH_NEE 0u       // NEE at s is next
#define GI_PATH_WAITING 1u   // for NEE's light or the continuation's hit
#define GI_PATH_CONTINUE 2u  // the continuation ray is next
#define GI_PATH_DONE 3u

struct GiPath {
  GiPathSample result;
  GiSurface s;     // the vertex being shaded (vertex `depth`)
  GiBsdf b;
  vec3 V;          // towards the previous vertex
  vec3 throughput;
  vec3 throughputDemod;
  float previousBsdfPdf;
  vec3 origin;     // the continuation ray
  vec3 direction;
  uint depth;
  uint maxBounces;
  uint russianRouletteStart;
  uint phase;      // GI_PATH_*
  uvec2 reservoir; // vertex 0's reservoir (a primary hit's, set by the module's passes), or GI_NO_RESERVOIR
};

GiPath giPathStart(GiSurface vertex0, vec3 V, uint maxBounces, uint russianRouletteStart) {
  GiPath p;
  p.result.direct = p.result.indirect = p.result.indirectDemod = vec3(0.0);
  p.s = vertex0;
  p.b = giMakeBsdf(vertex0.material.baseColor, vertex0.material.metallic, vertex0.material.roughness,
                   vertex0.material.flags);
  p.V = V;
  p.throughput = p.throughputDemod = vec3(1.0);
  p.previousBsdfPdf = 0.0;
  p.origin = p.direction = vec3(0.0);
  p.depth = 0u;
  p.maxBounces = maxBounces;
  p.russianRouletteStart = russianRouletteStart;
  p.phase = GI_PATH_NEE;
  p.reservoir = GI_NO_RESERVOIR;
  return p;
}

uint giPathNext(inout GiPath p, GiRng rng, out GiRay ray, out GiNeeRequest nee) {
  if (p.phase == GI_PATH_NEE) {
    nee = GiNeeRequest(p.s, p.b, p.V, true, rng, p.depth == 0u ? p.reservoir : GI_NO_RESERVOIR);
    p.phase = GI_PATH_WAITING;
    return GI_STEP_NEE;
  }
  if (p.phase == GI_PATH_CONTINUE) {
    ray = giClosestRay(p.origin, p.direction, 0.0, GI_FLT_MAX);
    p.phase = GI_PATH_WAITING;
    return GI_STEP_TRACE;
  }
  return GI_STEP_DONE;
}

// Light reflected at vertex `depth` (by NEE, or an emitter seen from it): direct at vertex 0, else indirect.
void giPathAdd(inout GiPath p, vec3 light, bool atVertex0) {
  if (atVertex0) p.result.direct += p.throughput * light;  // at vertex 0 the throughput is still 1
  else {
    p.result.indirect += p.throughput * light;
    p.result.indirectDemod += p.throughputDemod * light;
  }
}

// NEE's light at the vertex; then the BSDF sample that continues the path.
void giPathTakeNee(inout GiPath p, vec3 light, inout GiRng rng) {
  giPathAdd(p, light, p.depth == 0u);
  vec3 L, weight;
  float pdf;
  vec3 u = vec3(giRandom2(rng), giRandom(rng));
  p.phase = GI_PATH_DONE;
  if (!giBsdfSample(p.b, p.s.normal, p.V, u, L, weight, pdf)) return;
  if (dot(L, p.s.geometricNormal) <= 0.0) return;  // would pass through the surface
  p.throughputDemod = p.depth == 0u ? vec3(max(dot(p.s.normal, L), 0.0) * GI_INV_PI / pdf) : p.throughputDemod * weight;
  p.throughput *= weight;
  if (p.depth + 1u >= p.russianRouletteStart) {
    float survive = clamp(giMaxComponent(p.throughput), 0.05, 0.95);
    if (giRandom(rng) >= survive) return;
    p.throughput /= survive;
    p.throughputDemod /= survive;
  }
  p.previousBsdfPdf = pdf;
  p.origin = giOffsetRay(p.s.position, p.s.geometricNormal);
  p.direction = L;
  p.phase = GI_PATH_CONTINUE;
}

// The continuation's hit: vertex depth + 1 (light found there has taken `depth` bounces).
void giPathTakeHit(inout GiPath p, GiHit hit, GiSurface s) {
  p.depth++;
  p.phase = GI_PATH_DONE;
  // From vertex 0, whose reservoir holds the emissive triangles (its NEE samples only the sky), an emitter
  // found by BSDF sampling is the reservoir's light: not counted again. Where it holds the sky, the sky found
  // so takes the part of its light the reservoir's MIS weight leaves (giReservoirSkyPdf).
  const bool reservoirVertex = p.depth == 1u && giUsesReservoir(p.reservoir);
  const bool triangles = !(reservoirVertex && giReservoirsHoldEmissive());
  const bool sky = !(reservoirVertex && giReservoirsSampleSky());
  if (hit.t < 0.0) {  // the sky, weighed against its NEE (giPrepareSky) or the reservoir's share of it
    if (GI_SCENE_HAS_SKY) {
      const float lightPdf = sky ? giSkyNeePdf(p.direction, p.s, triangles) : giReservoirSkyPdf(p.direction, p.s);
      giPathAdd(p, giSkyRadiance(p.direction) * giPowerHeuristic(p.previousBsdfPdf, lightPdf), p.depth == 1u);
    }
    return;
  }
  if (triangles && s.frontFace && giMaxComponent(s.material.emission) > 0.0) {
    float w = GI_SCENE_HAS_EMISSIVE ? giPowerHeuristic(p.previousBsdfPdf, giEmissiveNeePdf(s, hit, p.origin, p.s, sky)) : 1.0;
    giPathAdd(p, s.material.emission * w, p.depth == 1u);
  }
  p.s = s;
  if (p.depth > p.maxBounces) return;
  p.V = -p.direction;
  p.b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
  p.phase = GI_PATH_NEE;
}

#endif
