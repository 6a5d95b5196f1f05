// The sky: the light of rays that leave the scene (GpuSceneConstants' sky
// fields), and its shadow ray for next-event estimation (lights.glsl picks
// between it and the emissive triangles).
//  - A constant sky is reached by BSDF sampling where the caller combines
//    strategies (withMis: the map-less sky has no light pdf to weigh), and by
//    cosine-distributed shadow rays where NEE stands alone.
//  - A map is importance sampled by luminance × sin θ (piecewise constant over
//    its texels: SCENE_BINDING_SKY_DISTRIBUTION holds the row CDF, then one
//    column CDF per row) and weighed against BSDF sampling by MIS.
#ifndef GI_SKY_GLSL
#define GI_SKY_GLSL
#include "bsdf.glsl"
#include "random.glsl"
#include "surface.glsl"

layout(set = 0, binding = SCENE_BINDING_SKY_DISTRIBUTION) uniform textureBuffer sceneSkyCdfTexels;  // R32_SFLOAT
float sceneSkyCdf(uint i) { return GI_FETCH(sceneSkyCdfTexels, int(i)).r; }

bool giSkyHasMap() { return GI_SCENE_HAS_SKY && sceneConstants().skyTexture != NO_TEXTURE; }

// Texel of the map a direction falls in.
ivec2 giSkyTexel(vec3 dir) {
  float u = 0.5 + atan(dir.x, -dir.z) * (0.5 * GI_INV_PI);
  float v = acos(clamp(dir.y, -1.0, 1.0)) * GI_INV_PI;
  ivec2 size = ivec2(sceneConstants().skySize);
  return clamp(ivec2(vec2(u, v) * vec2(size)), ivec2(0), size - 1);
}

vec3 giSkyRadiance(vec3 dir) {
  if (!GI_SCENE_HAS_SKY) return vec3(0.0);
  vec3 L = sceneConstants().skyRadiance;
  if (sceneConstants().skyTexture != NO_TEXTURE)
    L *= texelFetch(GI_TEXTURE(sceneConstants().skyTexture), giSkyTexel(dir), 0).rgb;
  return L;
}

// Probability of texel (column x, row y) under the tables.
float giSkyTexelProbability(ivec2 t) {
  uint w = sceneConstants().skySize.x, h = sceneConstants().skySize.y;
  float row = sceneSkyCdf(uint(t.y)) - (t.y > 0 ? sceneSkyCdf(uint(t.y - 1)) : 0.0);
  uint base = h + uint(t.y) * w;
  float column = sceneSkyCdf(base + uint(t.x)) - (t.x > 0 ? sceneSkyCdf(base + uint(t.x) - 1u) : 0.0);
  return row * column;
}

// Solid-angle density with which NEE picks `dir` (0 without a map: the
// constant sky is not sampled where strategies are combined).
float giSkyLightPdf(vec3 dir) {
  if (!giSkyHasMap()) return 0.0;
  float sinTheta = sqrt(max(1.0 - dir.y * dir.y, 0.0));
  if (sinTheta <= 0.0) return 0.0;
  float texels = float(sceneConstants().skySize.x * sceneConstants().skySize.y);
  return giSkyTexelProbability(giSkyTexel(dir)) * texels / (2.0 * GI_PI * GI_PI * sinTheta);
}

// First index in [first, first + count) whose CDF value exceeds u.
uint giSkySearch(uint first, uint count, float u) {
  uint lo = 0u, hi = count - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (sceneSkyCdf(first + mid) <= u) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}

// Where u falls within entry i of the CDF starting at `first`, in [0,1).
float giSkyRemap(uint first, uint i, float u) {
  float lo = i > 0u ? sceneSkyCdf(first + i - 1u) : 0.0, hi = sceneSkyCdf(first + i);
  return hi > lo ? clamp((u - lo) / (hi - lo), 0.0, 0.99999994) : 0.5;
}

// A direction drawn from the map's tables, and its solid-angle density.
vec3 giSampleSkyMap(vec2 u, out float pdf) {
  uint w = sceneConstants().skySize.x, h = sceneConstants().skySize.y;
  uint y = giSkySearch(0u, h, u.x);
  uint x = giSkySearch(h + y * w, w, u.y);
  // Uniform within the texel (the density is constant over it), from what is left of u.
  float uu = (float(x) + giSkyRemap(h + y * w, x, u.y)) / float(w);
  float vv = (float(y) + giSkyRemap(0u, y, u.x)) / float(h);
  float phi = 2.0 * GI_PI * (uu - 0.5), theta = GI_PI * vv;
  float sinTheta = sin(theta);
  vec3 dir = vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
  pdf = sinTheta > 0.0 ? giSkyTexelProbability(ivec2(x, y)) * float(w * h) / (2.0 * GI_PI * GI_PI * sinTheta) : 0.0;
  return dir;
}

// The sky's shadow ray, picked with probability `selection` (giSkySelection:
// never with MIS for a constant sky, which BSDF sampling finds). A map is
// sampled by its tables and, withMis, weighed against BSDF sampling; a
// constant sky by cosine-distributed directions.
bool giPrepareSky(GiSurface s, GiBsdf b, vec3 V, bool withMis, float selection, inout GiRng rng, out GiShadowRay ray) {
  vec2 u = giRandom2(rng);
  vec3 L;
  float pdf;
  if (giSkyHasMap()) {
    L = giSampleSkyMap(u, pdf);
  } else {
    L = giCosineSample(s.normal, u);
    pdf = max(dot(L, s.normal), 0.0) * GI_INV_PI;
  }
  pdf *= selection;
  if (!(pdf > 0.0) || dot(s.geometricNormal, L) <= 0.0) return false;
  vec3 f = giBsdfEval(b, s.normal, V, L);
  vec3 Le = giSkyRadiance(L);
  if (giMaxComponent(f * Le) <= 0.0) return false;
  float mis = withMis ? giPowerHeuristic(pdf, giBsdfPdf(b, s.normal, V, L)) : 1.0;
  ray.origin = giOffsetRay(s.position, s.geometricNormal);
  ray.direction = L;
  ray.tMax = GI_FLT_MAX;
  ray.contribution = f * Le * (mis / pdf);
  return true;
}

#endif
