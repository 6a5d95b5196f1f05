#version 460
// Path space filtering at every diffuse vertex (Meijer 2019 §4.3–4.4).
//  nhpsf:  per pixel and sample, a walk of pathDepth segments from the
//          primary hit; each diffuse vertex's cell gets the radiance that one
//          segment brings it (NEE at the next vertex plus that vertex's
//          albedo × its cell from last frame's map).
//  anhpsf: per pixel and sample, the primary segment; then one segment of the
//          pixel's continued walk (2 rays: the segment and its shadow ray),
//          stored across frames up to continuationDepth segments in all (the
//          primary segment is the first). The deepest live walk continues; a
//          dead or finished one restarts where this frame's primary segment landed. Light found deep down feeds the
//          cells along the walk and reaches the primary cells through the map.
// The primary vertex's walk uses a cosine direction whatever its material:
// the cell (and the pixel's own fallback sample) holds demodulated light. It
// feeds the primary cell when the vertex has a diffuse lobe (giHasDiffuseLobe).
// Direct light takes one NEE sample per path, averaged like the indirect.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf_walk.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

// A pixel's work as a ray task (ray_loop.glsl): per sample, NEE at the
// primary vertex, then its walk's segments; then (anhpsf) one segment of the
// pixel's continued walk.
#define NH_PRIMARY_NEE 0u  // the primary vertex's NEE is next
#define NH_WAITING 1u      // for its light
#define NH_WALK 2u         // a walk's segments
#define NH_DONE 3u

struct GiTask {
  uint phase;  // NH_*
  GiSurface s;
  GiBsdf b;
  vec3 V;
  HgDescriptor d0;    // the primary vertex's cell
  bool filterVertex;  // it has a diffuse lobe
  GiRng rng;
  uint sampleIndex;
  uint segment;       // segments this sample's walk has taken
  bool continuing;    // the walk is the pixel's continued one (anhpsf)
  HgWalk walk, restart, stored;
  HgStep step;
  uvec2 reservoir;    // the primary vertex's (reservoirs.glsl)
  vec3 direct, indirect;
};

uint giTaskNext(inout GiTask t, out GiRay ray, out GiNeeRequest nee) {
  for (;;) {
    if (t.phase == NH_PRIMARY_NEE) {
      nee = GiNeeRequest(t.s, t.b, t.V, false, t.rng, t.reservoir);
      t.phase = NH_WAITING;
      return GI_STEP_NEE;
    }
    if (t.phase != NH_WALK) return GI_STEP_DONE;
    const uint step = hgStepNext(t.step, t.walk, t.rng, ray, nee);
    if (step != GI_STEP_DONE) return step;
    // A segment is done.
    if (t.continuing) {
      t.stored = t.walk;
      t.phase = NH_DONE;
      continue;
    }
    if (t.segment == 0u) t.indirect += t.step.arriving;  // the primary segment: the pixel's own sample
    t.segment++;
    const uint segments = pc.mode == HG_MODE_NHPSF ? pc.depth : 1u;
    if (t.segment < segments && hgWalkDepth(t.walk) > 0u) {
      t.step = hgStepStart(t.walk);
      continue;
    }
    if (hgWalkDepth(t.restart) == 0u) t.restart = t.walk;
    t.sampleIndex++;
    t.phase = t.sampleIndex < pc.samplesPerPixel ? NH_PRIMARY_NEE : NH_DONE;
    if (t.phase == NH_DONE && pc.mode == HG_MODE_ANHPSF) {
      // The deepest live walk with segments left continues (a walk that has
      // taken k segments sits at vertex k + 1); otherwise this frame's.
      if (hgWalkDepth(t.stored) == 0u || hgWalkSegments(t.stored) >= pc.depth) t.stored = t.restart;
      if (hgWalkDepth(t.stored) > 0u && hgWalkSegments(t.stored) < pc.depth) {
        t.walk = t.stored;
        t.continuing = true;
        t.step = hgStepStart(t.walk);
        t.phase = NH_WALK;
      }
    }
  }
}

void giTaskTakeNee(inout GiTask t, vec3 light, GiRng rng) {
  if (t.phase == NH_WAITING) {  // the primary vertex's
    t.rng = rng;
    t.direct += light;
    t.walk = hgWalkFrom(t.s, t.d0, t.filterVertex, 1u, hgPrimaryTravel(t.s.position), t.rng);
    t.segment = 0u;
    t.step = hgStepStart(t.walk);
    t.phase = NH_WALK;
    return;
  }
  hgStepTakeNee(t.step, light, rng, t.rng);
}

void giTaskTakeHit(inout GiTask t, GiHit hit, GiSurface s) { hgStepTakeHit(t.step, hit, s); }

#include "ray_loop.glsl"

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  uint continued = 0u, depthSum = 0u;
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;
    uint pixel = uint(p.y) * giFrame.size.x + uint(p.x);
    HgWalk stored;
    stored.state = 0u;
    if (pc.mode == HG_MODE_ANHPSF) stored = hgUnpackWalk(HG_AT(hgWalks, pixel));
    if (giGbCoveredCounting(p)) {
      GiTask t;
      t.s = giGbSurface(p, t.V);
      GiRng hashRng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
      t.d0 = hgPrimaryDescriptor(t.s.position, t.s.normal, hashRng);
      t.filterVertex = filterVertex = giHasDiffuseLobe(t.s.material);
      t.rng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_MODULE);
      t.b = giMakeBsdf(t.s.material.baseColor, t.s.material.metallic, t.s.material.roughness, t.s.material.flags);
      t.phase = NH_PRIMARY_NEE;
      t.reservoir = giPrimaryReservoir(p);
      t.sampleIndex = 0u;
      t.continuing = false;
      t.restart.state = 0u;
      t.stored = stored;
      t.direct = t.indirect = vec3(0.0);
      giRunTask(t);
      direct = t.s.material.emission + t.direct / float(pc.samplesPerPixel);
      indirect = t.indirect / float(pc.samplesPerPixel);
      if (pc.mode == HG_MODE_ANHPSF) {
        stored = t.stored;
        continued = hgWalkDepth(stored) > 0u ? 1u : 0u;
        depthSum = hgWalkSegments(stored);
      }
    } else {
      stored.state = 0u;  // background: nothing to continue
    }
    if (pc.mode == HG_MODE_ANHPSF) HG_AT(hgWalks, pixel) = hgPackWalk(stored);
    giStoreDirect(p, direct);
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  uint sumContinued = subgroupAdd(continued), sumDepth = subgroupAdd(depthSum);
  if (subgroupElect() && sumContinued > 0u) {
    atomicAdd(hgTelemetry.continued, sumContinued);
    atomicAdd(hgTelemetry.depthSum, sumDepth);
  }
  hgFlushTelemetry();
  giCountRays(inside);
}
