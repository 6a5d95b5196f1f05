// Stale radiance: each cell keeps one sentinel ray (from the vertex that made
// it) and what it saw: the hit distance and the light NEE finds at the hit
// (two half floats, hpsf.glsl's hgPackSentinelSeen), with random numbers
// seeded by the cell's key. Re-tracing it later gives
// exactly the same two numbers unless geometry or lights moved (Meijer 2019
// §7 suggests re-tracing stored rays), so a static scene never touches a
// cell's history. When they differ, resolve weighs the change against the
// cell's noise (hpsf_resolve.comp).
#ifndef GI_HPSF_SENTINEL_GLSL
#define GI_HPSF_SENTINEL_GLSL
#include "lights.glsl"
#include "surface.glsl"
#include "random.glsl"

// The sentinel as a part of a ray task (ray_loop.glsl): its ray, then NEE at
// the hit. Once hgSentinelNext says GI_STEP_DONE, `distance_` is the hit
// distance (< 0 on a miss) and `light` the NEE luminance at the hit.
#define HG_SENTINEL_TRACE 0u    // the sentinel ray is next
#define HG_SENTINEL_WAITING 1u  // for its hit or its NEE
#define HG_SENTINEL_NEE 2u      // NEE at the hit is next
#define HG_SENTINEL_DONE 3u

struct HgSentinel {
  vec3 origin;
  vec3 direction;
  uint key;
  uint phase;  // HG_SENTINEL_*
  float distance_;
  float light;
  GiNeeRequest nee;  // at the hit
};

HgSentinel hgSentinelStart(vec3 origin, vec3 direction, uint key) {
  HgSentinel p;
  p.origin = origin;
  p.direction = direction;
  p.key = key;
  p.phase = HG_SENTINEL_TRACE;
  p.distance_ = -1.0;
  p.light = 0.0;
  return p;
}

uint hgSentinelNext(inout HgSentinel p, out GiRay ray, out GiNeeRequest nee) {
  if (p.phase == HG_SENTINEL_TRACE) {
    ray = giClosestRay(p.origin, p.direction, 0.0, GI_FLT_MAX);
    p.phase = HG_SENTINEL_WAITING;
    return GI_STEP_TRACE;
  }
  if (p.phase == HG_SENTINEL_NEE) {
    nee = p.nee;
    p.phase = HG_SENTINEL_WAITING;
    return GI_STEP_NEE;
  }
  return GI_STEP_DONE;
}

void hgSentinelTakeHit(inout HgSentinel p, GiHit hit, GiSurface w) {
  p.phase = HG_SENTINEL_DONE;
  if (hit.t < 0.0) return;
  p.distance_ = hit.t;
  GiBsdf b = giMakeBsdf(w.material.baseColor, w.material.metallic, w.material.roughness, w.material.flags);
  // Random numbers seeded by the cell's key: a re-trace draws the same ones.
  p.nee = GiNeeRequest(w, b, -p.direction, false, giRngCreate(uvec2(p.key, 0x9e3779b9u), 0u, 0u, GI_STREAM_HASH),
                         GI_NO_RESERVOIR);
  p.phase = HG_SENTINEL_NEE;
}

void hgSentinelTakeNee(inout HgSentinel p, vec3 light) {
  p.light = giLuminance(light);
  p.phase = HG_SENTINEL_DONE;
}

#endif
