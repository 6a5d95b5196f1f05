// Set 2 of the path-space-filtering passes: the hash map (shared/hash_grid.h)
// and its insert-or-find with bounded linear probing (Meijer Alg. 4).
#ifndef GI_HPSF_GLSL
#define GI_HPSF_GLSL
#include "bounds.glsl"
#include "common.glsl"
#include "shared/hash_grid.h"

layout(set = 2, binding = HG_BINDING_KEYS, scalar) buffer HgKeys { uint hgKeys[]; };
layout(set = 2, binding = HG_BINDING_ACCUM, scalar) buffer HgAccums { HgAccum hgAccum[]; };
layout(set = 2, binding = HG_BINDING_CELLS, scalar) buffer HgCells { HgCell hgCells[]; };
layout(set = 2, binding = HG_BINDING_TELEMETRY, scalar) buffer HgTelemetryBlock { HgTelemetry hgTelemetry; };
layout(set = 2, binding = HG_BINDING_COUNTS, scalar) buffer HgCounts { uint hgCounts[]; };
layout(set = 2, binding = HG_BINDING_CONTINUATION, scalar) buffer HgWalks { HgWalkRecord hgWalks[]; };

// Element i of one of the arrays above; with ModuleDesc::checkBounds, an i outside it is counted and
// element 0 taken instead (bounds.glsl).
uint hgChecked(uint i, int length) {
  if (GI_CHECK_BOUNDS && i >= uint(length)) {
    atomicAdd(hgTelemetry.outOfBounds, 1u);
    return 0u;
  }
  return i;
}
#define HG_AT(array, i) array[hgChecked(uint(i), array.length())]

// A walk's state word: vertices reached, whether the next segment continues
// a counted sample, and the fed cell's level of detail.
uint hgWalkState(uint depth, bool continues, int lod) {
  return (depth & 0xffffu) | (continues ? 0x10000u : 0u) | (uint(clamp(lod + 128, 0, 255)) << 24u);
}
uint hgWalkDepth(HgWalk w) { return w.state & 0xffffu; }
uint hgWalkSegments(HgWalk w) { return max(hgWalkDepth(w), 1u) - 1u; }
bool hgWalkContinues(HgWalk w) { return (w.state & 0x10000u) != 0u; }
int hgWalkLod(HgWalk w) { return int(w.state >> 24u) - 128; }

// HgWalkRecord's fields (shared/hash_grid.h).
uint hgPackSnorm13x2(vec2 v) {
  const uvec2 q = uvec2(ivec2(round(clamp(v, -1.0, 1.0) * 4095.0)) & 0x1fff);
  return q.x | (q.y << 13u);
}
vec2 hgUnpackSnorm13x2(uint v) {
  const ivec2 q = (ivec2(uvec2(v, v >> 13u) & 0x1fffu) << 19) >> 19;  // sign-extended
  return max(vec2(q) / 4095.0, -1.0);
}
uint hgPackUfloat11(float x) {  // an unsigned half float to 6 mantissa bits, rounded to nearest
  return min((packHalf2x16(vec2(clamp(x, 0.0, 65024.0), 0.0)) + 0x8u) >> 4u, 0x7bfu);
}
float hgUnpackUfloat11(uint v) { return unpackHalf2x16((v & 0x7ffu) << 4u).x; }

HgWalkRecord hgPackWalk(HgWalk w) {
  const uint direction = hgPackSnorm13x2(unpackSnorm2x16(w.direction));
  const uint lod = uint(clamp(hgWalkLod(w) + 32, 0, 63));
  const uint state = min(hgWalkDepth(w), 31u) << 26u | (hgWalkContinues(w) ? 1u << 31u : 0u);
  const uint index = w.index & ((1u << HG_WALK_INDEX_BITS) - 1u);
  return HgWalkRecord(w.origin, w.key, direction | lod << 26u, giPackRgbShared(w.throughput, 7u, vec3(0.5)) | state,
                      index | hgPackUfloat11(w.travel) << HG_WALK_INDEX_BITS);
}
HgWalk hgUnpackWalk(HgWalkRecord r) {
  const uint direction = packSnorm2x16(hgUnpackSnorm13x2(r.directionLod));
  const uint state = hgWalkState((r.throughputState >> 26u) & 31u, (r.throughputState >> 31u) != 0u,
                                 int(r.directionLod >> 26u) - 32);
  return HgWalk(r.origin, r.indexTravel & ((1u << HG_WALK_INDEX_BITS) - 1u),
                giUnpackRgbShared(r.throughputState & 0x3ffffffu, 7u), r.key, direction,
                hgUnpackUfloat11(r.indexTravel >> HG_WALK_INDEX_BITS), state, 0u);
}

// The global slot holding `key` in the table starting at `table`, or -1.
// With `create` a missing key claims a slot (`created`); without, it is only
// found. Meijer's Alg. 4 in two passes over the probe window: first look for
// the key (stepping over tombstones, stopping at an empty slot, beyond which
// no chain continues); if it is not there, claim the first empty or tombstone
// slot by compare-exchange, taking the slot instead if a concurrent insert of
// the same key got there first. Every inserter of a key walks the window in
// the same order, so concurrent inserts of one key agree on one slot.
// With `deferred` (HgPush::deferredClaims) a missing key claims nothing now:
// it bids for its first free slot with `priority` (HG_SLOT_ASKED comes
// back), and the largest bid, priority then key, gets the slot after the
// frame's inserts (hgClaimAsked). No slot changes hands while inserts run, so
// every inserter of a key finds the same first free slot, and which keys get
// slots, and where, follows from the bids, not from the order the threads ran
// in: a full map turns the same samples away every run. The passes bid with a
// random priority a sample: a key more samples ask for wins more often, as it
// would by asking first.
#define HG_SLOT_NONE -1   // no slot: the key is missing, and the probe window is full (or it was only looked for)
#define HG_SLOT_ASKED -2  // deferred: the key asked for a slot, which it has from the next frame on
int hgInsertOrFind(uint table, uint index, uint key, uint capacity, uint window, bool create, bool deferred,
                   uint priority, out uint probes, out bool created) {
  created = false;
  probes = window;
  uint firstFree = window;
  for (uint i = 0u; i < window; ++i) {
    uint k = HG_AT(hgKeys, table + ((index + i) & (capacity - 1u)));
    if (k == key) {
      probes = i + 1u;
      return int(table + ((index + i) & (capacity - 1u)));
    }
    if (k == HG_TOMBSTONE_KEY && firstFree == window) firstFree = i;
    if (k == HG_EMPTY_KEY) {
      if (firstFree == window) firstFree = i;
      break;
    }
  }
  if (!create || firstFree == window) return HG_SLOT_NONE;
  if (deferred) {
    atomicMax(HG_AT(hgAccum, table + ((index + firstFree) & (capacity - 1u))).lum2, (uint64_t(priority) << 32) | key);
    return HG_SLOT_ASKED;
  }
  for (uint i = firstFree; i < window; ++i) {
    uint slot = table + ((index + i) & (capacity - 1u));
    uint seen = HG_AT(hgKeys, slot);
    if (seen == HG_EMPTY_KEY || seen == HG_TOMBSTONE_KEY) {
      uint previous = atomicCompSwap(HG_AT(hgKeys, slot), seen, key);
      if (previous == seen) {
        probes = i + 1u;
        created = true;
        return int(slot);
      }
      seen = previous;
    }
    if (seen == key) {
      probes = i + 1u;
      return int(slot);
    }
  }
  return HG_SLOT_NONE;
}

// Read-only lookup (no claim): the global slot holding `key`, or -1.
int hgFind(uint table, uint index, uint key, uint capacity, uint window) {
  for (uint i = 0u; i < window; ++i) {
    uint slot = table + ((index + i) & (capacity - 1u));
    uint k = HG_AT(hgKeys, slot);
    if (k == key) return int(slot);
    if (k == HG_EMPTY_KEY) return -1;
  }
  return -1;
}

// A slot's frame sums with the samples behind them (two arrays: HG_BINDING_ACCUM, HG_BINDING_COUNTS).
struct HgFrameSums {
  HgAccum sums;
  uint count;
};
HgFrameSums hgLoadFrameSums(uint slot) { return HgFrameSums(HG_AT(hgAccum, slot), HG_AT(hgCounts, slot)); }
void hgStoreFrameSums(uint slot, HgFrameSums f) {
  HG_AT(hgAccum, slot) = f.sums;
  HG_AT(hgCounts, slot) = f.count;
}

// Zeroes a slot's frame sums.
void hgClearAccum(uint slot) {
  HgAccum zero;
  zero.r = zero.g = zero.b = zero.tr = zero.tg = zero.tb = zero.lum2 = 0ul;
  hgStoreFrameSums(slot, HgFrameSums(zero, 0u));
}

// A cell with no history and no sentinel.
HgCell hgEmptyCell() {
  HgCell empty;
  empty.mean = vec3(0.0);
  empty.lumMoment2 = 0.0;
  empty.tail = vec3(0.0);
  empty.frames = 0.0;
  empty.recent = 0u;
  empty.lastSeen = 0u;
  empty.sentinelOrigin = vec3(0.0);
  empty.sentinelSeen = 0u;
  empty.sentinelDirection = 0u;
  empty.samples = 0u;
  empty.previousLod = 0u;
  return empty;
}

// Removes the cell in `slot` (global) of the table starting at `table`. Its
// sums and history go with it, so the next key to claim the slot starts from
// nothing. The slot becomes a tombstone, which keeps the probe chains through
// it intact (a key further along stays reachable, and is not inserted a
// second time); or empty when the next slot is empty, since no chain
// continues past an empty slot. Runs only in resolve, where no insert runs
// concurrently: slots there only ever empty, so a neighbour read as empty
// stays empty, and one read as full at worst leaves a tombstone that a later
// frame's resolve turns empty.
void hgEvict(uint table, uint slot, uint capacity) {
  uint next = table + ((slot - table + 1u) & (capacity - 1u));
  HG_AT(hgKeys, slot) = HG_AT(hgKeys, next) == HG_EMPTY_KEY ? HG_EMPTY_KEY : HG_TOMBSTONE_KEY;
  hgClearAccum(slot);
  HG_AT(hgCells, slot) = hgEmptyCell();
}

// A tombstone whose next slot is empty ends no chain any more: it becomes empty too.
void hgTidyTombstone(uint table, uint slot, uint capacity) {
  uint next = table + ((slot - table + 1u) & (capacity - 1u));
  if (HG_AT(hgKeys, slot) == HG_TOMBSTONE_KEY && HG_AT(hgKeys, next) == HG_EMPTY_KEY) HG_AT(hgKeys, slot) = HG_EMPTY_KEY;
}

// Deferred claims, once per slot of `table` after the frame's inserts: a free slot that keys bid for
// becomes the cell of the largest bid's key, empty, seen this frame (so resolve keeps it). True when it did.
bool hgClaimAsked(uint table, uint slot, uint frameIndex) {
  const uint64_t bid = HG_AT(hgAccum, table + slot).lum2;
  const uint held = HG_AT(hgKeys, table + slot);
  if (bid == 0ul || (held != HG_EMPTY_KEY && held != HG_TOMBSTONE_KEY)) return false;  // a live cell's sums are no bid
  HG_AT(hgAccum, table + slot).lum2 = 0ul;
  HG_AT(hgKeys, table + slot) = uint(bid & 0xfffffffful);  // free when bid for, and no slot changed hands since
  HgCell c = hgEmptyCell();
  c.lastSeen = frameIndex;
  HG_AT(hgCells, table + slot) = c;
  return true;
}

// Adds one sample (count 1: r, g, b, luminance², count), or more light for a
// sample already counted (count 0: r, g, b only), with what the outlier clamp
// took off it (`tail`, 3 more atomics where not zero). `radiance`, `tail` and
// `momentLuminance` are already multiplied by the push constants'
// radianceScale; the second moment is of `momentLuminance`, which the clamp
// passes unclamped (hgInsertSample says why). Returns the frame's samples in
// the cell before this one (0xffffffff for more light, count 0).
uint hgAccumulate(int slot, vec3 radiance, vec3 tail, float momentLuminance, uint count, inout bool overflowed) {
  if (any(greaterThan(radiance + tail, vec3(float(HG_MAX_SAMPLE))))) overflowed = true;
  atomicAdd(HG_AT(hgAccum, slot).r, hgToFixed(radiance.r));
  atomicAdd(HG_AT(hgAccum, slot).g, hgToFixed(radiance.g));
  atomicAdd(HG_AT(hgAccum, slot).b, hgToFixed(radiance.b));
  if (any(greaterThan(tail, vec3(0.0)))) {
    atomicAdd(HG_AT(hgAccum, slot).tr, hgToFixed(tail.r));
    atomicAdd(HG_AT(hgAccum, slot).tg, hgToFixed(tail.g));
    atomicAdd(HG_AT(hgAccum, slot).tb, hgToFixed(tail.b));
  }
  if (count == 0u) return 0xffffffffu;
  atomicAdd(HG_AT(hgAccum, slot).lum2, hgToFixed(min(momentLuminance * momentLuminance, float(HG_MAX_SAMPLE))));
  return atomicAdd(HG_AT(hgCounts, slot), count);
}

// Walk directions are stored octahedral in 2 × 16 bits (HgWalk::direction, HgCell::sentinelDirection).
uint hgPackDirection(vec3 d) { return packSnorm2x16(giOctahedralEncode(d)); }
vec3 hgUnpackDirection(uint packed) {
  vec2 o = unpackSnorm2x16(packed);
  vec3 d = vec3(o, 1.0 - abs(o.x) - abs(o.y));
  if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
  return normalize(d);
}

// What a sentinel saw as its cell keeps it (HgCell::sentinelSeen): half floats, the hit distance in
// metres (< 0: missed) and the NEE luminance at the hit · radianceScale (the map's units, so that a
// half's range, up to 65504 times SceneDesc::typicalRadiance, holds it), each clamped to a half's
// largest. A re-trace that finds the same float finds the same half: a static scene still answers
// exactly as before. 0 is no sentinel (a hit at 0 m that sees no light).
uint hgPackSentinelSeen(float distance_, float light, float radianceScale) {
  return packHalf2x16(vec2(min(distance_, 65504.0), min(light * radianceScale, 65504.0)));
}

// How far the cell's mean has moved, as far as the sentinel can tell (luminance,
// the cell's units), from what it saw then and sees now (hgPackSentinelSeen). The
// sentinel is one sample of the cell's own estimator (a cosine ray and NEE at its
// hit), re-traced with the same random numbers, so the difference of its two
// answers is a one-sample estimate of the change of the cell's mean; 0 when the
// scene answers the same up to float noise (a light within 0.1%). A different hit
// (another half float of distance, which a move by more than 0.1% of it always
// gives and a smaller one may not; a ray that hit misses, or the reverse) changes
// the light from beyond it, which NEE cannot see: then the change is taken to be
// at least the cell's mean.
float hgSentinelChange(uint then, uint now, float cellMean, float radianceScale) {
  const bool sameHit = (then & 0xffffu) == (now & 0xffffu);
  const float lightThen = unpackHalf2x16(then).y / radianceScale, lightNow = unpackHalf2x16(now).y / radianceScale;
  float change = abs(lightNow - lightThen);
  if (change <= 1e-3 * max(lightThen, 1e-6)) change = 0.0;
  return sameHit ? change : max(change, cellMean);
}

// A cell's recent mean (HgCell::recent): RGB9E5 of radiance · radianceScale (a constant of the module),
// rounded stochastically with a dither of its key and frame (not its slot, which the order of the inserts
// may change), so the running mean it is blends nothing away (shared/hash_grid.h).
vec3 hgCellRecent(HgCell c, float radianceScale) { return giUnpackRgb9e5(c.recent) / radianceScale; }
uint hgPackRecent(vec3 recent, float radianceScale, uint key, uint frameIndex) {
  const uint h = hgHashPcg(key ^ hgHashPcg(frameIndex)), h2 = hgHashPcg(h);  // 16 bits a channel: a frame that
  const vec3 dither = (vec3(uvec3(h, h >> 16u, h2) & 0xffffu) + 0.5) / 65536.0;  // moves it 1/65536 step counts
  return giPackRgbShared(recent * radianceScale, 9u, dither);
}

// A cell's radiance: the mean of its clamped samples plus the clamp's tail.
vec3 hgCellRadiance(HgCell c) { return c.mean + c.tail; }

#endif
