// Set 2 of the path-space-filtering passes: the hash map (shared/hash_grid.h)
// and its insert-or-find with bounded linear probing (Meijer Alg. 4).
#ifndef GI_HPSF_GLSL
#define GI_HPSF_GLSL
#include "shared/hash_grid.h"

layout(set = 2, binding = HG_BINDING_KEYS, scalar) buffer HgKeys { uint hgKeys[]; };
layout(set = 2, binding = HG_BINDING_ACCUM, scalar) buffer HgAccums { HgAccum hgAccum[]; };
layout(set = 2, binding = HG_BINDING_CELLS, scalar) buffer HgCells { HgCell hgCells[]; };
layout(set = 2, binding = HG_BINDING_TELEMETRY, scalar) buffer HgTelemetryBlock { HgTelemetry hgTelemetry; };
layout(set = 2, binding = HG_BINDING_PIXEL_CELL, r32ui) uniform uimage2D hgPixelCell;
layout(set = 2, binding = HG_BINDING_CONTINUATION, scalar) buffer HgWalks { HgWalk hgWalks[]; };

// The global slot holding `key` in the table starting at `table` (claimed if
// free: `created`), or -1 when the probe window is full.
int hgInsertOrFind(uint table, uint index, uint key, uint capacity, uint window, out uint probes, out bool created) {
  created = false;
  for (uint i = 0u; i < window; ++i) {
    uint slot = table + ((index + i) & (capacity - 1u));
    uint previous = atomicCompSwap(hgKeys[slot], HG_EMPTY_KEY, key);
    if (previous == HG_EMPTY_KEY || previous == key) {
      probes = i + 1u;
      created = previous == HG_EMPTY_KEY;
      return int(slot);
    }
  }
  probes = window;
  return -1;
}

// Read-only lookup (no claim): the global slot holding `key`, or -1.
int hgFind(uint table, uint index, uint key, uint capacity, uint window) {
  for (uint i = 0u; i < window; ++i) {
    uint slot = table + ((index + i) & (capacity - 1u));
    uint k = hgKeys[slot];
    if (k == key) return int(slot);
    if (k == HG_EMPTY_KEY) return -1;
  }
  return -1;
}

// Adds one sample (count 1: 5 atomics, r, g, b, luminance², count), or more
// light for a sample already counted (count 0: r, g, b only). `radiance` and
// `momentLuminance` are already multiplied by the push constants'
// radianceScale; the second moment is of `momentLuminance`, which the outlier
// clamp passes unclamped (hgInsertSample says why).
void hgAccumulate(int slot, vec3 radiance, float momentLuminance, uint count, inout bool overflowed) {
  vec3 v = radiance;
  if (any(greaterThan(v, vec3(float(HG_MAX_SAMPLE))))) overflowed = true;
  atomicAdd(hgAccum[slot].r, hgToFixed(v.r));
  atomicAdd(hgAccum[slot].g, hgToFixed(v.g));
  atomicAdd(hgAccum[slot].b, hgToFixed(v.b));
  if (count == 0u) return;
  atomicAdd(hgAccum[slot].lum2, hgToFixed(min(momentLuminance * momentLuminance, float(HG_MAX_SAMPLE))));
  atomicAdd(hgAccum[slot].count, count);
}

#endif
