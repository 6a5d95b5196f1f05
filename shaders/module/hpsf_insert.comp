#version 460
// Hashed path space filtering, insert (Meijer 2019 Alg. 1–4): per pixel, N
// paths from the primary hit, which is the filter vertex when its material
// has a diffuse lobe (giHasDiffuseLobe). The demodulated indirect radiance
// arriving there (throughput reset at the vertex; albedo never multiplied
// in) goes into the cell of the vertex's jittered, quantised position. Direct
// light stays per pixel. A pure metal has no diffuse lobe: the composite
// gives its diffuse indirect light no weight, so it is not filtered.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf_walk.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

// A pixel's work as a ray task (ray_loop.glsl): its paths, then the sentinel of
// the cell it made, if it made one.
struct GiTask {
  GiSurface s;
  vec3 V;
  ivec2 p;
  uint sampleIndex;
  GiPath path;
  GiRng rng;
  float kept;          // paths kept (finite)
  vec3 direct, indirect;
  bool sentinelOut;        // the paths are done; the sentinel is out
  int slot;            // the cell the pixel made, while its sentinel is out
  HgSentinel sentinel;
};

GiRng hgSampleRng(ivec2 p, uint i) {
  return giRngCreate(uvec2(p), pc.frameIndex * pc.samplesPerPixel + i, pc.seed, GI_STREAM_MODULE);
}

// The pixel's mean goes into its filter vertex's cell.
void hgInsertPixel(inout GiTask t) {
  float inv = 1.0 / max(t.kept, 1.0);
  t.direct = t.s.material.emission + t.direct * inv;
  t.indirect *= inv;
  t.sentinelOut = true;
  t.sentinel.phase = HG_SENTINEL_DONE;
  if (!giHasDiffuseLobe(t.s.material)) return;
  GiRng rng = giRngCreate(uvec2(t.p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
  HgDescriptor d = hgPrimaryDescriptor(t.s.position, t.s.normal, rng);
  vec3 sentinelOrigin = giOffsetRay(t.s.position, t.s.geometricNormal);
  vec3 sentinelDirection = giCosineSample(t.s.normal, giRandom2(rng));
  // The lookup finds this cell again from the same surface and random numbers (hgPixelCell).
  const uint key = hgVerificationKey(d);
  bool needsSentinel;
  const int slot = hgInsertSample(hgIndexHash(d), key, t.indirect, 1u, d.lod, needsSentinel);
  if (!needsSentinel) return;
  t.slot = slot;
  t.sentinel = hgNewCellSentinel(sentinelOrigin, sentinelDirection, key);
}

uint giTaskNext(inout GiTask t, out GiRay ray, out GiNeeRequest nee) {
  if (!t.sentinelOut) {
    for (;;) {
      const uint step = giPathNext(t.path, t.rng, ray, nee);
      if (step != GI_STEP_DONE) return step;
      GiPathSample path = t.path.result;
      if (giKeepSample(path.direct, path.indirectDemod)) {
        t.kept += 1.0;
        t.direct += path.direct;
        t.indirect += path.indirectDemod;
      }
      if (++t.sampleIndex == pc.samplesPerPixel) break;
      t.rng = hgSampleRng(t.p, t.sampleIndex);
      t.path = giPathStart(t.s, t.V, pc.maxBounces, pc.russianRouletteStart);
      t.path.reservoir = giPrimaryReservoir(t.p);
    }
    hgInsertPixel(t);
  }
  const uint step = hgSentinelNext(t.sentinel, ray, nee);
  if (step == GI_STEP_DONE && t.slot >= 0) {
    hgStoreSentinel(t.slot, t.sentinel);
    t.slot = -1;
  }
  return step;
}

void giTaskTakeHit(inout GiTask t, GiHit hit, GiSurface s) {
  if (t.sentinelOut) hgSentinelTakeHit(t.sentinel, hit, s);
  else giPathTakeHit(t.path, hit, s);
}

void giTaskTakeNee(inout GiTask t, vec3 light, GiRng rng) {
  if (t.sentinelOut) {
    hgSentinelTakeNee(t.sentinel, light);
    return;
  }
  t.rng = rng;
  giPathTakeNee(t.path, light, t.rng);
}

#include "ray_loop.glsl"

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;
    if (giGbCoveredCounting(p)) {
      GiTask t;
      t.s = giGbSurface(p, t.V);
      t.p = p;
      t.sampleIndex = 0u;
      t.rng = hgSampleRng(p, 0u);
      t.path = giPathStart(t.s, t.V, pc.maxBounces, pc.russianRouletteStart);
      t.path.reservoir = giPrimaryReservoir(p);
      t.kept = 0.0;
      t.direct = t.indirect = vec3(0.0);
      t.sentinelOut = false;
      t.slot = -1;
      giRunTask(t);
      direct = t.direct;
      indirect = t.indirect;
      filterVertex = giHasDiffuseLobe(t.s.material);
    }
    giStoreDirect(p, direct);
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  hgFlushTelemetry();
  giCountRays(inside);
}
