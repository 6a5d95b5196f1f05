// One hemisphere sample of axis-aligned filtering: a ray from the receiver,
// the reflector distance, and the radiance the reflector sends back (path
// traced beyond the first bounce), or 1 for ambient occlusion. Emission at
// the reflector is direct light, so it is left out.
//
// Diffuse receivers draw cosine-distributed rays. Glossy receivers (when the
// scene has any) draw from their BSDF's mixture of cosine and GGX lobes, and
// the one ray estimates both terms, each divided by the mixture's density:
// the demodulated diffuse term, and the specular term split as
// f0·(1 − s)·lobe + s·lobe (bsdf.glsl) so f0 is applied after filtering.
#ifndef GI_AAF_GLSL
#define GI_AAF_GLSL
#include "path.glsl"
#include "gi_frame.glsl"
#include "shared/aaf.h"

layout(push_constant, scalar) uniform Push { AafPush pc; };

struct AafSample {
  vec3 diffuse;       // demodulated: reflected radiance of a white Lambertian receiver
  vec3 specular;      // lobe·(1 − s)·L / pdf (glossy receivers only)
  vec3 specularEdge;  // lobe·s·L / pdf
  float hitDistance;  // metres; < 0 on a miss
};

// True where this pixel's receiver gets the separate glossy term.
bool aafGlossyReceiver(GiBsdf b) { return pc.glossy != 0u && pc.ambientOcclusion == 0u && b.specularProbability > 0.0; }

// The random number that picks a glossy receiver's lobe (diffuse receivers draw none).
float aafLobeChoice(GiBsdf b, inout GiRng rng) { return aafGlossyReceiver(b) ? giRandom(rng) : 0.0; }

AafSample aafSample(GiSurface s, GiBsdf b, vec3 V, vec3 u, inout GiRng rng) {
  AafSample r;
  r.diffuse = r.specular = r.specularEdge = vec3(0.0);
  r.hitDistance = -1.0;
  bool glossy = aafGlossyReceiver(b);
  vec3 dir, weight;
  float pdf;
  if (glossy) {
    if (!giBsdfSample(b, s.normal, V, u, dir, weight, pdf)) return r;
  } else {
    dir = giCosineSample(s.normal, u.xy);
    pdf = max(dot(dir, s.normal), 0.0) * GI_INV_PI;
  }
  if (dot(dir, s.geometricNormal) <= 0.0 || pdf <= 0.0) return r;
  GiHit hit = giTraceClosest(giOffsetRay(s.position, s.geometricNormal), dir, 0.0, GI_FLT_MAX);
  if (hit.t < 0.0) return r;
  r.hitDistance = hit.t;
  vec3 radiance = vec3(1.0);
  if (pc.ambientOcclusion == 0u) {
    GiSurface y = giSurfaceFromHit(hit, dir);
    GiPathSample path = giTracePathFromSurface(y, -dir, pc.maxBounces - 1u, pc.russianRouletteStart, rng);
    radiance = path.direct + path.indirect;
    if (!giKeepSample(radiance, vec3(0.0))) return r;
  }
  // Cosine sampling cancels cos/π against its density exactly.
  r.diffuse = glossy ? radiance * (max(dot(dir, s.normal), 0.0) * GI_INV_PI / pdf) : radiance;
  if (glossy) {
    float schlick;
    float lobe = giSpecularLobe(b, s.normal, V, dir, schlick) / pdf;
    r.specular = radiance * (lobe * (1.0 - schlick));
    r.specularEdge = radiance * (lobe * schlick);
  }
  return r;
}

#endif
