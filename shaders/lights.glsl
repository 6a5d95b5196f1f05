// Next-event estimation: one emissive triangle picked by power (with MIS
// against BSDF sampling), every punctual light (delta lights, no MIS) and
// the sky (sky.glsl).
// Specialisation constants (scene.glsl) drop the loops a scene does not need.
#ifndef GI_LIGHTS_GLSL
#define GI_LIGHTS_GLSL
#include "bsdf.glsl"
#include "random.glsl"
#include "surface.glsl"
#include "sky.glsl"


// Solid-angle density with which NEE would pick the emissive point `s` seen
// from `from` (s.frontFace must hold).
float giEmissiveLightPdf(GiSurface s, uint geometry, vec3 from) {
  if (!GI_SCENE_HAS_EMISSIVE) return 0.0;
  vec3 d = s.position - from;
  float dist2 = dot(d, d);
  float cosLight = abs(dot(s.geometricNormal, normalize(d)));
  float areaPdf = giLuminance(sceneMaterials[sceneGeometries[geometry].material].emission) / sceneConstants.emissiveTotalPower;
  return areaPdf * dist2 / max(cosLight, 1e-8);
}

uint giPickEmissiveTriangle(float u) {
  uint lo = 0u, hi = sceneConstants.emissiveTriangleCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (sceneEmissiveTriangles[mid].cdf <= u) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}

// withMis: weight against BSDF sampling (the caller also adds BSDF-sampled emission).
vec3 giSampleEmissive(GiSurface s, GiBsdf b, vec3 V, bool withMis, inout GiRng rng) {
  GpuEmissiveTriangle e = sceneEmissiveTriangles[giPickEmissiveTriangle(giRandom(rng))];
  uvec3 tri = sceneTriangle(e.geometry, e.triangle);
  vec2 u = giRandom2(rng);
  float su = sqrt(u.x);
  vec3 w = vec3(1.0 - su, su * (1.0 - u.y), su * u.y);
  vec3 p0, p1, p2, ns, ng;
  giTriangleWorld(e.instance, tri, p0, p1, p2);
  vec3 y = p0 * w.x + p1 * w.y + p2 * w.z;
  giTriangleNormals(e.instance, tri, w, p0, p1, p2, ns, ng);
  vec3 toLight = y - s.position;
  float dist2 = dot(toLight, toLight);
  if (!(dist2 > 0.0)) return vec3(0.0);
  float dist = sqrt(dist2);
  vec3 L = toLight / dist;
  float cosLight = dot(ng, -L);
  if (cosLight <= 0.0) return vec3(0.0);  // emission is one-sided
  vec3 f = giBsdfEval(b, s.normal, V, L);
  if (dot(s.geometricNormal, L) <= 0.0 || giMaxComponent(f) <= 0.0) return vec3(0.0);
  GpuMaterial m = sceneMaterials[sceneGeometries[e.geometry].material];
  vec3 Le = m.emission;
  if (m.emissiveTexture != NO_TEXTURE) Le *= sceneTexture(m.emissiveTexture, sceneUv(tri, w)).rgb;
  float lightPdf = giLuminance(m.emission) / sceneConstants.emissiveTotalPower * dist2 / cosLight;
  vec3 origin = giOffsetRay(s.position, s.geometricNormal);
  vec3 target = giOffsetRay(y, -L);
  vec3 seg = target - origin;
  float segLength = length(seg);
  if (!(segLength > 0.0) || !giTraceVisible(origin, seg / segLength, 0.0, segLength)) return vec3(0.0);
  float mis = withMis ? giPowerHeuristic(lightPdf, giBsdfPdf(b, s.normal, V, L)) : 1.0;
  return f * Le * (mis / lightPdf);
}

vec3 giSamplePunctual(GiSurface s, GiBsdf b, vec3 V) {
  vec3 sum = vec3(0.0);
  vec3 origin = giOffsetRay(s.position, s.geometricNormal);
  for (uint i = 0u; i < sceneConstants.punctualLightCount; ++i) {
    GpuPunctualLight l = scenePunctualLights[i];
    vec3 L;
    float tMax;
    vec3 radiance = l.intensity;  // becomes irradiance at the receiver (W/m²)
    if (l.type == PUNCTUAL_DIRECTIONAL) {
      L = -l.direction;
      tMax = GI_FLT_MAX;
    } else {
      vec3 d = l.position - origin;
      float dist2 = dot(d, d);
      if (!(dist2 > 0.0)) continue;
      float dist = sqrt(dist2);
      L = d / dist;
      tMax = dist;
      radiance /= dist2;
      if (l.range > 0.0) {  // KHR_lights_punctual's recommended smooth range window
        float r = dist / l.range;
        radiance *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
      }
      if (l.type == PUNCTUAL_SPOT) {
        float cd = dot(l.direction, -L);
        float scale = 1.0 / max(l.cosInner - l.cosOuter, 1e-4);
        float t = clamp((cd - l.cosOuter) * scale, 0.0, 1.0);
        radiance *= t * t;
      }
    }
    if (dot(s.geometricNormal, L) <= 0.0) continue;
    vec3 f = giBsdfEval(b, s.normal, V, L);
    if (giMaxComponent(f * radiance) <= 0.0) continue;
    if (giTraceVisible(origin, L, 0.0, tMax)) sum += f * radiance;
  }
  return sum;
}

// Reflected direct light at s towards V: f·cos·L / pdf for one emissive
// sample, all punctual lights and one sky sample. withMis as in giSampleEmissive.
vec3 giDirectLight(GiSurface s, GiBsdf b, vec3 V, bool withMis, inout GiRng rng) {
  vec3 sum = vec3(0.0);
  if (GI_SCENE_HAS_EMISSIVE && sceneConstants.emissiveTriangleCount > 0u) sum += giSampleEmissive(s, b, V, withMis, rng);
  if (GI_SCENE_HAS_PUNCTUAL) sum += giSamplePunctual(s, b, V);
  if (GI_SCENE_HAS_SKY) sum += giSampleSky(s, b, V, withMis, rng);
  return sum;
}

#endif
