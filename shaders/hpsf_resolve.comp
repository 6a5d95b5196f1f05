#version 460
// Hashed path space filtering, resolve: once per cell and frame, folds this
// frame's sums into the cell's history (a running mean capped at
// historyCap frames, SHaRC-style), evicts cells untouched for staleFrames,
// and counts what is left. Strict eviction (Meijer) is historyCap 2,
// staleFrames 1: a cell lives on only if touched again the next frame.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

void main() {
  uint slot = gl_GlobalInvocationID.x;
  uint live = 0u, evicted = 0u;
  if (slot < pc.capacity && hgKeys[slot] != HG_EMPTY_KEY) {
    HgAccum a = hgAccum[slot];
    HgCell c = hgCells[slot];
    if (a.count > 0u) {
      vec3 frameMean = vec3(hgFromFixed(a.r, a.count), hgFromFixed(a.g, a.count), hgFromFixed(a.b, a.count));
      float frameM2 = hgFromFixed(a.lum2, a.count);
      float w = 1.0 / (min(c.frames, float(pc.historyCap) - 1.0) + 1.0);
      c.mean = c.frames > 0.0 ? mix(c.mean, frameMean, w) : frameMean;
      c.lumMoment2 = c.frames > 0.0 ? mix(c.lumMoment2, frameM2, w) : frameM2;
      c.frames = min(c.frames + 1.0, float(pc.historyCap));
      // Samples behind the mean: this frame's plus the share of history the cap keeps.
      c.samples = a.count + uint(float(c.samples) * (1.0 - w));
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
  uint sumLive = subgroupAdd(live), sumEvicted = subgroupAdd(evicted);
  if (subgroupElect()) {
    if (sumLive > 0u) atomicAdd(hgTelemetry.occupied, sumLive);
    if (sumEvicted > 0u) atomicAdd(hgTelemetry.evicted, sumEvicted);
  }
}
