// One hemisphere sample of axis-aligned filtering: a cosine-distributed ray
// from the receiver, the reflector distance, and the radiance the reflector
// sends back (path traced beyond the first bounce), or 1 for ambient
// occlusion. Emission at the reflector is direct light, so it is left out.
#ifndef GI_AAF_GLSL
#define GI_AAF_GLSL
#include "path.glsl"
#include "gi_frame.glsl"
#include "shared/aaf.h"

layout(push_constant, scalar) uniform Push { AafPush pc; };

// Returns the reflected radiance (demodulated: cos/π/pdf = 1); hitDistance < 0 on a miss.
vec3 aafSample(GiSurface s, vec2 u, inout GiRng rng, out float hitDistance) {
  hitDistance = -1.0;
  vec3 dir = giCosineSample(s.normal, u);
  if (dot(dir, s.geometricNormal) <= 0.0) return vec3(0.0);
  GiHit hit = giTraceClosest(giOffsetRay(s.position, s.geometricNormal), dir, 0.0, GI_FLT_MAX);
  if (hit.t < 0.0) return vec3(0.0);
  hitDistance = hit.t;
  if (pc.ambientOcclusion != 0u) return vec3(1.0);
  GiSurface y = giSurfaceFromHit(hit, dir);
  GiPathSample path = giTracePathFromSurface(y, -dir, pc.maxBounces - 1u, pc.russianRouletteStart, rng);
  vec3 radiance = path.direct + path.indirect;
  return giKeepSample(radiance, vec3(0.0)) ? radiance : vec3(0.0);
}

#endif
