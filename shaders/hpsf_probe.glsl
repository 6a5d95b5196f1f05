// Stale radiance: each cell keeps one probe ray (from the vertex that made
// it) and what it saw: the hit distance and the light NEE finds at the hit,
// with random numbers seeded by the cell's key. Re-tracing it later gives
// exactly the same two numbers unless geometry or lights moved (Meijer 2019
// §7 suggests re-tracing stored rays), so a static scene never touches a
// cell's history. When they differ, resolve weighs the change against the
// cell's noise (hpsf_resolve.comp).
#ifndef GI_HPSF_PROBE_GLSL
#define GI_HPSF_PROBE_GLSL
#include "lights.glsl"
#include "surface.glsl"
#include "random.glsl"

// Traces the probe: distance (< 0 on a miss) and NEE luminance at the hit.
void hgTraceProbe(vec3 origin, vec3 direction, uint key, out float distance_, out float light) {
  distance_ = -1.0;
  light = 0.0;
  GiHit hit = giTraceClosest(origin, direction, 0.0, GI_FLT_MAX);
  if (hit.t < 0.0) return;
  distance_ = hit.t;
  GiSurface w = giSurfaceFromHit(hit, direction);
  GiBsdf b = giMakeBsdf(w.material.baseColor, w.material.metallic, w.material.roughness, w.material.flags);
  GiRng rng = giRngCreate(uvec2(key, 0x9e3779b9u), 0u, 0u, GI_STREAM_HASH);
  light = giLuminance(giDirectLight(w, b, -direction, false, rng));
}

// How far the cell's mean has moved, as far as the probe can tell (luminance,
// the cell's units). The probe is one sample of the cell's own estimator (a
// cosine ray and NEE at its hit), re-traced with the same random numbers, so
// the difference of its two answers is a one-sample estimate of the change of
// the cell's mean; 0 when the scene answers the same up to float noise. A
// different hit also changes the light from beyond it, which NEE cannot see:
// then the change is taken to be at least the cell's mean.
float hgProbeChange(float distanceThen, float lightThen, float distanceNow, float lightNow, float cellMean) {
  bool sameHit = (distanceThen < 0.0) == (distanceNow < 0.0) && abs(distanceNow - distanceThen) <= 1e-4 * max(distanceThen, 1e-3);
  float change = abs(lightNow - lightThen);
  if (change <= 1e-3 * max(lightThen, 1e-6)) change = 0.0;
  return sameHit ? change : max(change, cellMean);
}

#endif
