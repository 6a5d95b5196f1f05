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
#extension GL_KHR_shader_subgroup_vote : require
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

// One hemisphere sample as a part of a ray task (ray_loop.glsl): the ray
// to the reflector, then (unless ambient occlusion) the path from it. `r` is
// final once aafSamplerNext says GI_STEP_DONE.
#define AAF_SAMPLER_REFLECTOR 0u  // the ray to the reflector is next
#define AAF_SAMPLER_WAITING 1u
#define AAF_SAMPLER_PATH 2u       // the path from the reflector
#define AAF_SAMPLER_FINISH 3u     // `radiance` reached the receiver
#define AAF_SAMPLER_DONE 4u

struct AafSampler {
  uint phase;  // AAF_SAMPLER_*
  vec3 origin, dir;
  float pdf;
  bool glossy;
  vec3 radiance;  // the reflector's, towards the receiver
  AafSample r;
  GiPath path;
};

// The sample's direction from u: the receiver's BSDF mixture where glossy, else cosine.
AafSampler aafSamplerStart(GiSurface s, GiBsdf b, vec3 V, vec3 u) {
  AafSampler a;
  a.r.diffuse = a.r.specular = a.r.specularEdge = vec3(0.0);
  a.r.hitDistance = -1.0;
  a.phase = AAF_SAMPLER_DONE;
  a.glossy = aafGlossyReceiver(b);
  vec3 weight;
  if (a.glossy) {
    if (!giBsdfSample(b, s.normal, V, u, a.dir, weight, a.pdf)) return a;
  } else {
    a.dir = giCosineSample(s.normal, u.xy);
    a.pdf = max(dot(a.dir, s.normal), 0.0) * GI_INV_PI;
  }
  if (dot(a.dir, s.geometricNormal) <= 0.0 || a.pdf <= 0.0) return a;
  a.origin = giOffsetRay(s.position, s.geometricNormal);
  a.phase = AAF_SAMPLER_REFLECTOR;
  return a;
}

// The sample's terms from the radiance reaching the receiver along dir.
void aafSamplerFinish(inout AafSampler a, GiSurface s, GiBsdf b, vec3 V) {
  a.phase = AAF_SAMPLER_DONE;
  if (!giKeepSample(a.radiance, vec3(0.0))) return;
  // Cosine sampling cancels cos/π against its density exactly.
  a.r.diffuse = a.glossy ? a.radiance * (max(dot(a.dir, s.normal), 0.0) * GI_INV_PI / a.pdf) : a.radiance;
  if (a.glossy) {
    float schlick;
    float lobe = giSpecularLobe(b, s.normal, V, a.dir, schlick) / a.pdf;
    a.r.specular = a.radiance * (lobe * (1.0 - schlick));
    a.r.specularEdge = a.radiance * (lobe * schlick);
  }
}

uint aafSamplerNext(inout AafSampler a, GiSurface s, GiBsdf b, vec3 V, GiRng rng, out GiRay ray, out GiNeeRequest nee) {
  if (a.phase == AAF_SAMPLER_REFLECTOR) {
    ray = giClosestRay(a.origin, a.dir, 0.0, GI_FLT_MAX);
    a.phase = AAF_SAMPLER_WAITING;
    return GI_STEP_TRACE;
  }
  if (a.phase == AAF_SAMPLER_PATH) {
    const uint step = giPathNext(a.path, rng, ray, nee);
    if (step != GI_STEP_DONE) return step;
    a.radiance = a.path.result.direct + a.path.result.indirect;
    a.phase = AAF_SAMPLER_FINISH;
  }
  if (a.phase == AAF_SAMPLER_FINISH) aafSamplerFinish(a, s, b, V);
  return GI_STEP_DONE;
}

void aafSamplerTakeHit(inout AafSampler a, GiHit hit, GiSurface y) {
  if (a.phase == AAF_SAMPLER_PATH) {
    giPathTakeHit(a.path, hit, y);
    return;
  }
  a.phase = AAF_SAMPLER_DONE;
  if (hit.t < 0.0) return;
  a.r.hitDistance = hit.t;
  a.radiance = vec3(1.0);  // ambient occlusion
  a.phase = AAF_SAMPLER_FINISH;
  if (pc.ambientOcclusion != 0u) return;
  a.path = giPathStart(y, -a.dir, pc.maxBounces - 1u, pc.russianRouletteStart);
  a.phase = AAF_SAMPLER_PATH;
}

// A pixel's work as a ray task: NEE at the receiver (with `direct`), then
// n hemisphere samples, summed. The program defines aafSampleU: sample i's
// random numbers for aafSamplerStart.
vec3 aafSampleU(uint i, uint n, uint offset, GiBsdf b, inout GiRng rng);

#define AAF_TASK_NEE 0u      // NEE at the receiver is next
#define AAF_TASK_WAITING 1u  // for its light
#define AAF_TASK_SAMPLES 2u
#define AAF_TASK_DONE 3u

struct GiTask {
  uint phase;  // AAF_TASK_*
  GiSurface s;
  GiBsdf b;
  vec3 V;
  GiRng rng;
  uint i, n, offset;  // samples taken, to take; aafSampleU's offset
  bool sampling;      // sample i is out
  AafSampler hemisphere;  // sample i
  vec3 direct;        // NEE's light
  vec3 diffuse, specular, specularEdge;  // sums
  float zMin, zMax;   // of the reflectors seen (metres)
  uvec2 reservoir;    // the primary hit's, for its direct light (reservoirs.glsl), or GI_NO_RESERVOIR
};

GiTask aafTaskStart(GiSurface s, vec3 V, GiRng rng, bool direct, uint n, uint offset) {
  GiTask t;
  t.phase = direct ? AAF_TASK_NEE : AAF_TASK_SAMPLES;
  t.s = s;
  t.b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
  t.V = V;
  t.rng = rng;
  t.i = 0u;
  t.n = n;
  t.offset = offset;
  t.sampling = false;
  t.direct = t.diffuse = t.specular = t.specularEdge = vec3(0.0);
  t.zMin = GI_FLT_MAX;
  t.zMax = 0.0;
  t.reservoir = GI_NO_RESERVOIR;
  return t;
}

uint giTaskNext(inout GiTask t, out GiRay ray, out GiNeeRequest nee) {
  if (t.phase == AAF_TASK_NEE) {
    nee = GiNeeRequest(t.s, t.b, t.V, false, t.rng, t.reservoir);
    t.phase = AAF_TASK_WAITING;
    return GI_STEP_NEE;
  }
  // Samples start together: a lane whose sample has ended waits while another lane's goes on, so that
  // the subgroup's NEE and paths keep in step (ray_loop.glsl).
  const bool othersSampling = subgroupAny(t.sampling);
  while (t.phase == AAF_TASK_SAMPLES) {
    if (t.sampling) {
      const uint step = aafSamplerNext(t.hemisphere, t.s, t.b, t.V, t.rng, ray, nee);
      if (step != GI_STEP_DONE) return step;
      t.diffuse += t.hemisphere.r.diffuse;
      t.specular += t.hemisphere.r.specular;
      t.specularEdge += t.hemisphere.r.specularEdge;
      if (t.hemisphere.r.hitDistance >= 0.0) {
        t.zMin = min(t.zMin, t.hemisphere.r.hitDistance);
        t.zMax = max(t.zMax, t.hemisphere.r.hitDistance);
      }
      t.i++;
      t.sampling = false;
      return GI_STEP_WAIT;
    }
    if (t.i == t.n) {
      t.phase = AAF_TASK_DONE;
      break;
    }
    if (othersSampling) return GI_STEP_WAIT;
    const vec3 u = aafSampleU(t.i, t.n, t.offset, t.b, t.rng);
    t.hemisphere = aafSamplerStart(t.s, t.b, t.V, u);
    t.sampling = true;
  }
  return GI_STEP_DONE;
}

void giTaskTakeHit(inout GiTask t, GiHit hit, GiSurface s) { aafSamplerTakeHit(t.hemisphere, hit, s); }

void giTaskTakeNee(inout GiTask t, vec3 light, GiRng rng) {
  t.rng = rng;
  if (t.phase == AAF_TASK_WAITING) {
    t.direct = light;
    t.phase = AAF_TASK_SAMPLES;
  } else {
    giPathTakeNee(t.hemisphere.path, light, t.rng);
  }
}

#include "ray_loop.glsl"

// Pass 1 hands pass 2 the mean of its samples (in the noisy indirect's units) and their count (alpha), in
// the noisy indirect itself, which pass 2 overwrites with the mean of all: no image of its own. Loads give
// back the sum (rgb) and the count (a; 0 where no surface was seen).
void aafStorePartial(ivec2 p, vec3 sum, float count) { giStoreNoisy(p, count > 0.0 ? sum / count : vec3(0.0), count); }
vec4 aafLoadPartial(ivec2 p) {
  const vec4 partial = giLoadNoisyAndAlpha(p);  // one load: the mean and the count
  return vec4(partial.rgb * partial.a, partial.a);
}

#endif
