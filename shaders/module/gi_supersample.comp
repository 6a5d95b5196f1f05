#version 460
// Guided filtering's supersampling (Bauszat et al. 2011, §3.2): extra eye
// rays per pixel get their own direct light, and take their indirect light
// from the filtered map at whichever of the four surrounding guide rays is
// most similar in normal and depth (eqs. 3–5). A box filter combines them
// with the guide ray's own result.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lights.glsl"
#include "gi_frame.glsl"
#include "shared/gi_filters.h"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiSupersamplePush pc; };

// A pixel's supersamples as a ray task (ray_loop.glsl): each one's eye ray,
// then NEE at its hit.
#define SS_RAY 0u      // sample k's eye ray is next
#define SS_WAITING 1u
#define SS_NEE 2u      // NEE at its hit is next
#define SS_DONE 3u

struct GiTask {
  uint phase;  // SS_*
  ivec2 p;
  uint k;      // the sample
  GiRng rng;
  vec2 pos;    // its position in the image (pixels)
  vec3 dir;
  GiSurface s;
  GiBsdf b;
  vec3 sum;
};

uint giTaskNext(inout GiTask t, out GiRay ray, out GiNeeRequest nee) {
  if (t.phase == SS_RAY) {
    if (t.k == pc.supersamples) return GI_STEP_DONE;
    t.rng = giRngCreate(uvec2(t.p), giFrame.frameIndex * pc.supersamples + t.k, pc.seed, GI_STREAM_SUPERSAMPLE);
    t.pos = vec2(t.p) + giRandom2(t.rng);
    t.dir = giCameraRayDirection(giFrame.camera, t.pos);
    ray = giClosestRay(giFrame.camera.position, t.dir, 0.0, GI_FLT_MAX);
    t.phase = SS_WAITING;
    return GI_STEP_TRACE;
  }
  if (t.phase == SS_NEE) {
    nee = GiNeeRequest(t.s, t.b, -t.dir, false, t.rng, GI_NO_RESERVOIR);
    t.phase = SS_WAITING;
    return GI_STEP_NEE;
  }
  return GI_STEP_DONE;
}

void giTaskTakeHit(inout GiTask t, GiHit hit, GiSurface s) {
  if (hit.t < 0.0) {  // the background
    t.sum += giSkyRadiance(t.dir);
    t.k++;
    t.phase = SS_RAY;
    return;
  }
  t.s = s;
  t.b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
  t.phase = SS_NEE;
}

// The sample's direct light, and its indirect light from the most similar of
// the four guide rays around it (eqs. 3–5).
void giTaskTakeNee(inout GiTask t, vec3 light, GiRng rng) {
  t.rng = rng;
  vec3 direct = t.s.material.emission + light;
  float depth = giViewDepth(giFrame.camera, t.s.position);
  ivec2 size = ivec2(giFrame.size);
  ivec2 base = ivec2(floor(t.pos - 0.5));
  ivec2 guides[4] = ivec2[4](base, base + ivec2(1, 0), base + ivec2(0, 1), base + ivec2(1, 1));
  vec4 dn, dd;
  for (int i = 0; i < 4; ++i) {
    guides[i] = clamp(guides[i], ivec2(0), size - 1);
    bool covered = giGbCovered(guides[i]);
    vec3 n = covered ? giGbNormal(guides[i]) : -t.s.normal;
    float z = covered ? giGbViewDepth(guides[i]) : 0.0;
    dn[i] = length(t.s.normal - n);
    dd[i] = abs(depth - z);
  }
  int best = gifMostSimilarGuide(dn, dd);
  vec3 indirect = max(giLoadIndirect(guides[best]), vec3(0.0));
  t.sum += direct + t.b.diffuse * indirect;
  t.k++;
  t.phase = SS_RAY;
}

#include "ray_loop.glsl"

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  if (inside) {
    GiTask t;
    t.phase = SS_RAY;
    t.p = p;
    t.k = 0u;
    t.sum = giLoadComposite(p);  // the guide ray's own sample
    giRunTask(t);
    giStoreComposite(p, t.sum / float(pc.supersamples + 1u));
  }
  giCountRays(inside);
}
