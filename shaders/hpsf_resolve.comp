#version 460
// Hashed path space filtering, resolve: once per cell and frame, turns the
// frame's sums into the mean the lookup reads, applies the eviction policy,
// and counts what is left.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"
#include "hpsf_probe.glsl"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

// A cell's probe, re-traced as a ray task (ray_loop.glsl).
struct GiTask {
  HgProbe probe;
};
uint giTaskNext(inout GiTask task, out GiRay ray, out GiNeeRequest nee) { return hgProbeNext(task.probe, ray, nee); }
void giTaskTakeHit(inout GiTask task, GiHit hit, GiSurface s) { hgProbeTakeHit(task.probe, hit, s); }
void giTaskTakeNee(inout GiTask task, vec3 light, GiRng rng) { hgProbeTakeNee(task.probe, light); }
#include "ray_loop.glsl"

// What the cell's probe sees now: its hit distance and NEE light. Called at one place.
void hgRetraceProbe(HgCell c, uint key, out float distance_, out float light) {
  GiTask task = GiTask(hgProbeStart(c.probeOrigin, hgUnpackDirection(c.probeDirection), key));
  giRunTask(task);
  distance_ = task.probe.distance_;
  light = task.probe.light;
}

// Strict eviction (Meijer §4.2.2): the cell's sums are this frame's samples
// plus everything its key held in the last frame's table, written back so
// that the next frame finds them there in turn: a cell touched every frame
// keeps its whole history. Cells of the last frame's table that nobody found
// this frame die with it (its table is cleared before it is written again).
#define HG_STRICT_MAX_COUNT 1073741824u  // 2^30 samples: halve the sums (same mean) before the count could wrap
void resolveStrict(uint i, inout uint live, inout uint evicted) {
  uint slot = pc.table + i;
  if (hgKeys[slot] != HG_EMPTY_KEY) {
    HgAccum a = hgAccum[slot];
    HgCell c = hgCells[slot];
    c.frames = 1.0;
    const uint previous = hgCellPrevious(c.previousLod);
    if (previous > 0u && pc.forgetLight == 0u) {
      HgAccum b = hgAccum[previous - 1u];
      a.r += b.r;
      a.g += b.g;
      a.b += b.b;
      a.tr += b.tr;
      a.tg += b.tg;
      a.tb += b.tb;
      a.lum2 += b.lum2;
      a.count += b.count;
      c.frames = hgCells[previous - 1u].frames + 1.0;
    }
    if (a.count >= HG_STRICT_MAX_COUNT) {
      a.r /= 2ul;
      a.g /= 2ul;
      a.b /= 2ul;
      a.tr /= 2ul;
      a.tg /= 2ul;
      a.tb /= 2ul;
      a.lum2 /= 2ul;
      a.count /= 2u;
    }
    hgAccum[slot] = a;
    c.mean = vec3(hgFromFixed(a.r, a.count), hgFromFixed(a.g, a.count), hgFromFixed(a.b, a.count)) / pc.radianceScale;
    c.tail = vec3(hgFromFixed(a.tr, a.count), hgFromFixed(a.tg, a.count), hgFromFixed(a.tb, a.count)) / pc.radianceScale;
    c.lumMoment2 = hgFromFixed(a.lum2, a.count) / (pc.radianceScale * pc.radianceScale);
    c.samples = a.count;
    c.lastSeen = pc.frameIndex;
    hgCells[slot] = c;
    live = 1u;
  }
  uint previous = pc.previousTable + i;
  if (hgKeys[previous] != HG_EMPTY_KEY && hgCells[previous].lastSeen != pc.frameIndex) evicted = 1u;
}

// This frame's mean of the clamped samples.
vec3 frameMean(HgAccum a) {
  return vec3(hgFromFixed(a.r, a.count), hgFromFixed(a.g, a.count), hgFromFixed(a.b, a.count)) / pc.radianceScale;
}

// Aging eviction (SHaRC-style): a running mean capped at historyCap frames;
// the outlier clamp's tail averaged over HG_TAIL_HISTORY times as many
// frames; cells untouched for staleFrames are evicted. nhpsf and anhpsf build
// the deep bounces through the map frame by frame (a segment brings the next
// vertex's cell from last frame), so a mean that lags delays every bounce
// after it: on Sponza the light still grew past frame 128 with a 20-frame
// history. What a cell passes on to the vertices before it is therefore its
// `recent` mean over the last historySamples samples only; the pixel shows
// the long one. The transported light is a little noisier, and it is
// averaged again in the receiving cell.
void resolveAging(uint slot, inout uint live, inout uint evicted, inout uint reset) {
  uint key = hgKeys[slot];
  if (key == HG_EMPTY_KEY) return;
  if (key == HG_TOMBSTONE_KEY) {
    hgTidyTombstone(pc.table, slot, pc.capacity);
    return;
  }
  HgAccum a = hgAccum[slot];
  HgCell c = hgCells[slot];
  // The windows in frames (c.frames counts on, for the tail's longer one).
  // They depend on the sample count only, never on the radiance: a window
  // that followed the cell's own σ/μ would stretch after every bright sample
  // and keep it longer (measured: +7% light on Sponza with hpsf).
  float cap = float(pc.historyCap);
  float recentCap = cap;
  if (pc.historySamples > 0u && a.count > 0u) recentCap = clamp(float(pc.historySamples) / float(a.count), 1.0, cap);
  // Stale radiance: every validationInterval frames (staggered over cells)
  // the probe is re-traced. If the cell's mean moved by Δ, a history of n
  // frames carries a bias of about Δ while its noise is σ²/n (σ² the variance
  // of one frame's mean), so the history is cut to n = σ²/Δ² frames, where
  // bias and noise match (A-SVGF's temporal gradients, Schied et al. 2018,
  // weighed against the cell's noise rather than its value). A change lost in
  // the noise keeps the history; a shadow that moved across the probe
  // restarts it. Resetting on any change cost Conference accuracy: one of its
  // four lights moving changed every probe that picked that light.
  bool hasProbe = pc.validationInterval > 0u && (c.probeDistance != 0.0 || c.probeLight != 0.0);
  bool validate = hasProbe && c.frames > 0.0 && (slot + pc.frameIndex) % pc.validationInterval == 0u;
  float distance_ = c.probeDistance, light = c.probeLight;
  if (pc.forgetLight != 0u ? hasProbe : validate) hgRetraceProbe(c, key, distance_, light);
  if (pc.forgetLight != 0u) {
    // The engine says the lights changed: the history goes, and every probe
    // learns the new light now (so that its next check does not cut again).
    // The cell keeps its key and its probe; until this frame's samples (if
    // any) restart its mean, it is not read.
    c.probeDistance = distance_;
    c.probeLight = light;
    c.frames = 0.0;
    c.samples = 0u;
    hgCells[slot] = c;
  } else if (validate) {
    float mean = giLuminance(c.mean);
    float change = hgProbeChange(c.probeDistance, c.probeLight, distance_, light, mean);
    if (change > 0.0) {
      float window = min(c.frames, cap);
      float samplesPerFrame = max(float(c.samples) / window, 1.0);
      float frameVariance = max(c.lumMoment2 - mean * mean, 0.0) / samplesPerFrame;
      float kept = floor(min(window, frameVariance / (change * change)));
      if (kept < window) {
        c.samples = uint(float(c.samples) * kept / window);
        c.frames = kept;
        reset = 1u;
      }
      c.probeDistance = distance_;
      c.probeLight = light;
      hgCells[slot] = c;
    }
  }
  if (a.count > 0u) {
    vec3 frameMean = frameMean(a);
    vec3 frameTail = vec3(hgFromFixed(a.tr, a.count), hgFromFixed(a.tg, a.count), hgFromFixed(a.tb, a.count)) / pc.radianceScale;
    float frameM2 = hgFromFixed(a.lum2, a.count) / (pc.radianceScale * pc.radianceScale);
    float w = 1.0 / (min(c.frames, cap - 1.0) + 1.0);
    float wTail = 1.0 / (min(c.frames, cap * HG_TAIL_HISTORY - 1.0) + 1.0);
    float wRecent = 1.0 / (min(c.frames, recentCap - 1.0) + 1.0);
    c.mean = c.frames > 0.0 ? mix(c.mean, frameMean, w) : frameMean;
    c.recent = c.frames > 0.0 ? mix(c.recent, frameMean, wRecent) : frameMean;
    c.tail = c.frames > 0.0 ? mix(c.tail, frameTail, wTail) : frameTail;
    c.lumMoment2 = c.frames > 0.0 ? mix(c.lumMoment2, frameM2, w) : frameM2;
    c.frames = min(c.frames + 1.0, float(pc.historyCap) * HG_TAIL_HISTORY);
    // Samples behind the mean: all of them while the mean weighs every frame
    // equally; once the cap turns it into an exponential average, this
    // frame's plus the (1 − w) share of the history it keeps.
    float kept = c.frames <= cap ? 1.0 : 1.0 - w;
    c.samples = a.count + uint(float(c.samples) * kept + 0.5);
    c.lastSeen = pc.frameIndex;
    hgCells[slot] = c;
    hgClearAccum(slot);
    live = 1u;
  } else if (pc.frameIndex - c.lastSeen >= pc.staleFrames) {
    hgEvict(pc.table, slot, pc.capacity);
    evicted = 1u;
  } else {
    live = 1u;
  }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint live = 0u, evicted = 0u, reset = 0u;
  if (i < pc.capacity) {
    if (pc.strict != 0u) resolveStrict(i, live, evicted);
    else resolveAging(pc.table + i, live, evicted, reset);
  }
  uint sumLive = subgroupAdd(live), sumEvicted = subgroupAdd(evicted), sumReset = subgroupAdd(reset);
  if (subgroupElect()) {
    if (sumLive > 0u) atomicAdd(hgTelemetry.occupied, sumLive);
    if (sumEvicted > 0u) atomicAdd(hgTelemetry.evicted, sumEvicted);
    if (sumReset > 0u) atomicAdd(hgTelemetry.staleResets, sumReset);
  }
}
