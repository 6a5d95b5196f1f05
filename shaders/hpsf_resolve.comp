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

// Strict eviction: the cell's mean is the exact fixed-point sum of this
// frame's samples and the last frame's samples of the same key; cells of the
// last frame's table that nobody found this frame die with it.
void resolveStrict(uint i, inout uint live, inout uint evicted) {
  uint slot = pc.table + i;
  if (hgKeys[slot] != HG_EMPTY_KEY) {
    HgAccum a = hgAccum[slot];
    HgCell c = hgCells[slot];
    c.frames = 1.0;
    if (c.previous > 0u && pc.forgetLight == 0u) {
      HgAccum b = hgAccum[c.previous - 1u];
      a.r += b.r;
      a.g += b.g;
      a.b += b.b;
      a.lum2 += b.lum2;
      a.count += b.count;
      c.frames = 2.0;
    }
    c.mean = vec3(hgFromFixed(a.r, a.count), hgFromFixed(a.g, a.count), hgFromFixed(a.b, a.count)) / pc.radianceScale;
    c.lumMoment2 = hgFromFixed(a.lum2, a.count) / (pc.radianceScale * pc.radianceScale);
    c.samples = a.count;
    c.lastSeen = pc.frameIndex;
    hgCells[slot] = c;
    live = 1u;
  }
  uint previous = pc.previousTable + i;
  if (hgKeys[previous] != HG_EMPTY_KEY && hgCells[previous].lastSeen != pc.frameIndex) evicted = 1u;
}

// Aging eviction (SHaRC-style): a running mean capped at historyCap frames;
// cells untouched for staleFrames are evicted.
void resolveAging(uint slot, inout uint live, inout uint evicted, inout uint reset) {
  if (hgKeys[slot] == HG_EMPTY_KEY) return;
  HgAccum a = hgAccum[slot];
  HgCell c = hgCells[slot];
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
  if (pc.forgetLight != 0u) {
    // The engine says the lights changed: the history goes, and every probe
    // learns the new light now (so that its next check does not cut again).
    if (hasProbe) hgTraceProbe(c.probeOrigin, c.probeDirection, hgKeys[slot], c.probeDistance, c.probeLight);
    c.frames = 0.0;
    c.samples = 0u;
    hgCells[slot] = c;
  } else if (hasProbe && c.frames > 0.0 && (slot + pc.frameIndex) % pc.validationInterval == 0u) {
    float distance_, light;
    hgTraceProbe(c.probeOrigin, c.probeDirection, hgKeys[slot], distance_, light);
    float mean = giLuminance(c.mean);
    float change = hgProbeChange(c.probeDistance, c.probeLight, distance_, light, mean);
    if (change > 0.0) {
      float samplesPerFrame = max(float(c.samples) / c.frames, 1.0);
      float frameVariance = max(c.lumMoment2 - mean * mean, 0.0) / samplesPerFrame;
      float kept = floor(min(c.frames, frameVariance / (change * change)));
      if (kept < c.frames) {
        c.samples = uint(float(c.samples) * kept / c.frames);
        c.frames = kept;
        reset = 1u;
      }
      c.probeDistance = distance_;
      c.probeLight = light;
      hgCells[slot] = c;
    }
  }
  if (a.count > 0u) {
    vec3 frameMean = vec3(hgFromFixed(a.r, a.count), hgFromFixed(a.g, a.count), hgFromFixed(a.b, a.count)) / pc.radianceScale;
    float frameM2 = hgFromFixed(a.lum2, a.count) / (pc.radianceScale * pc.radianceScale);
    float w = 1.0 / (min(c.frames, float(pc.historyCap) - 1.0) + 1.0);
    c.mean = c.frames > 0.0 ? mix(c.mean, frameMean, w) : frameMean;
    c.lumMoment2 = c.frames > 0.0 ? mix(c.lumMoment2, frameM2, w) : frameM2;
    c.frames = min(c.frames + 1.0, float(pc.historyCap));
    // Samples behind the mean: all of them while the mean weighs every frame
    // equally; once the cap turns it into an exponential average, this
    // frame's plus the (1 − w) share of the history it keeps.
    float kept = c.frames < float(pc.historyCap) ? 1.0 : 1.0 - w;
    c.samples = a.count + uint(float(c.samples) * kept + 0.5);
    c.lastSeen = pc.frameIndex;
    hgCells[slot] = c;
    hgAccum[slot].r = 0ul;
    hgAccum[slot].g = 0ul;
    hgAccum[slot].b = 0ul;
    hgAccum[slot].lum2 = 0ul;
    hgAccum[slot].count = 0u;
    live = 1u;
  } else if (pc.frameIndex - c.lastSeen >= pc.staleFrames || c.frames == 0.0) {
    hgKeys[slot] = HG_EMPTY_KEY;
    hgCells[slot].mean = vec3(0.0);
    hgCells[slot].lumMoment2 = 0.0;
    hgCells[slot].frames = 0.0;
    hgCells[slot].lastSeen = 0u;
    hgCells[slot].samples = 0u;
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
