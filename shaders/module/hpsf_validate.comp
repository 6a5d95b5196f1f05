#version 460
// Hashed path space filtering, stale radiance (aging eviction), before
// resolve: every validationInterval frames (staggered over cells) a cell's
// sentinel is re-traced. If the cell's mean moved by Δ, a history of n frames
// carries a bias of about Δ while its noise is σ²/n (σ² the variance of one
// frame's mean), so the history is cut to n = σ²/Δ² frames, where bias and
// noise match (A-SVGF's temporal gradients, Schied et al. 2018, weighed
// against the cell's noise rather than its value). A change lost in the
// noise keeps the history; a shadow that moved across the sentinel restarts it.
// Resetting on any change cost Conference accuracy: one of its four lights
// moving changed every sentinel that picked that light.
// A pass of its own, not part of resolve: lavapipe's compile time grows
// faster than a program's size, and the sentinel's ray loop is most of it.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "gi_frame.glsl"  // set 1: where the bounds-checked variant counts (bounds.glsl)
#include "hpsf.glsl"
#include "hpsf_sentinel.glsl"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

// A cell's sentinel, re-traced as a ray task (ray_loop.glsl).
struct GiTask {
  HgSentinel sentinel;
};
uint giTaskNext(inout GiTask task, out GiRay ray, out GiNeeRequest nee) { return hgSentinelNext(task.sentinel, ray, nee); }
void giTaskTakeHit(inout GiTask task, GiHit hit, GiSurface s) { hgSentinelTakeHit(task.sentinel, hit, s); }
void giTaskTakeNee(inout GiTask task, vec3 light, GiRng rng) { hgSentinelTakeNee(task.sentinel, light); }
#include "ray_loop.glsl"

// What the cell's sentinel sees now: its hit distance and NEE light, packed as the cell keeps them. Called
// at one place.
uint hgRetraceSentinel(HgCell c, uint key) {
  GiTask task = GiTask(hgSentinelStart(c.sentinelOrigin, hgUnpackDirection(c.sentinelDirection), key));
  giRunTask(task);
  return hgPackSentinelSeen(task.sentinel.distance_, task.sentinel.light, pc.radianceScale);
}

// Returns 1 when the cell's history was cut.
uint validate(uint slot) {
  uint key = HG_AT(hgKeys, slot);
  if (key == HG_EMPTY_KEY || key == HG_TOMBSTONE_KEY) return 0u;
  HgCell c = HG_AT(hgCells, slot);
  bool hasSentinel = c.sentinelSeen != 0u;
  bool due = hasSentinel && c.frames > 0.0 && (slot + pc.frameIndex) % pc.validationInterval == 0u;
  if (!(pc.forgetLight != 0u ? hasSentinel : due)) return 0u;
  const uint seen = hgRetraceSentinel(c, key);
  if (pc.forgetLight != 0u) {
    // The engine says the lights changed (resolve drops the history): every
    // sentinel learns the new light now, so that its next check does not cut again.
    HG_AT(hgCells, slot).sentinelSeen = seen;
    return 0u;
  }
  float mean = giLuminance(c.mean);
  float change = hgSentinelChange(c.sentinelSeen, seen, mean, pc.radianceScale);
  if (change <= 0.0) return 0u;
  uint reset = 0u;
  float window = min(c.frames, float(pc.historyCap));
  float samplesPerFrame = max(float(c.samples) / window, 1.0);
  float frameVariance = max(c.lumMoment2 - mean * mean, 0.0) / samplesPerFrame;
  float kept = floor(min(window, frameVariance / (change * change)));
  if (kept < window) {
    HG_AT(hgCells, slot).samples = uint(float(c.samples) * kept / window);
    HG_AT(hgCells, slot).frames = kept;
    reset = 1u;
  }
  HG_AT(hgCells, slot).sentinelSeen = seen;
  return reset;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint reset = i < pc.capacity ? validate(pc.table + i) : 0u;
  uint sumReset = subgroupAdd(reset);
  if (subgroupElect() && sumReset > 0u) atomicAdd(hgTelemetry.staleResets, sumReset);
}
