// Path space filtering's world-space hash map (Meijer 2019 Alg. 2–5, Binder et
// al. 2018), with an aging policy after NVIDIA SHaRC. Everything here is
// shared verbatim by C++ (CPU reference tests) and GLSL (hpsf_*.comp).
// Positions in metres; radiance is demodulated (a white Lambertian's).
#ifndef GI_HASH_GRID_H
#define GI_HASH_GRID_H
// GLSL users enable GL_EXT_shader_explicit_arithmetic_types_int64 (and
// GL_EXT_shader_atomic_int64 for the sums) before including this header.
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST HG_EMPTY_KEY = 0u;             // keys are never 0 (hgVerificationKey sets bit 0)
GPU_CONST HG_TOMBSTONE_KEY = 2u;         // an evicted slot that a probe chain still passes through (bit 0 clear:
                                         // never a key); inserts may reclaim it, lookups step over it
#define HG_FIXED_POINT_SCALE 65536.0     // radiance is summed as uint64 in units of 2^-16
#define HG_MAX_SAMPLE 1.0e9              // a sample above this (after clamping) counts as an overflow
#define HG_COORD_LIMIT 1073741824.0      // |cell coordinate| < 2^30 keeps int32 arithmetic exact

// Set 2 of the hash passes. The buffers hold one table of `capacity` slots
// (aging eviction) or two (strict eviction, Meijer: the tables swap every
// frame; the one written this frame starts empty, the other holds the last
// frame). Slot indices in the shaders are global: table base + slot.
GPU_CONST HG_BINDING_KEYS = 0;       // uint[tables·capacity]: verification keys, 0 = empty
GPU_CONST HG_BINDING_ACCUM = 1;      // HgAccum[tables·capacity]: a frame's sums (atomics); aging clears them in resolve
GPU_CONST HG_BINDING_CELLS = 2;      // HgCell[tables·capacity]: resolved means
GPU_CONST HG_BINDING_TELEMETRY = 3;  // HgTelemetry: counters of the current frame
GPU_CONST HG_BINDING_COUNTS = 4;     // uint[tables·capacity]: the samples HgAccum sums (atomics), apart from the
                                     // sums: beside them a count took 8 bytes a cell (the sums' alignment)
GPU_CONST HG_BINDING_CONTINUATION = 5; // HgWalk[pixels]: anhpsf's paths continued over frames

GPU_CONST HG_MODE_HPSF = 0u;         // full paths from the primary hit; the primary cell filters
GPU_CONST HG_MODE_NHPSF = 1u;        // pathDepth segments; every diffuse vertex's cell filters
GPU_CONST HG_MODE_ANHPSF = 2u;       // one primary segment + one continued segment per pixel and frame

// The travel that sets a secondary vertex's level of detail (gi::SecondaryLod).
GPU_CONST HG_LOD_SEGMENT = 0u;       // Alg. 1/3 as written: unfiltered travel (through glossy vertices) + this segment
GPU_CONST HG_LOD_PATH = 1u;          // the whole path's travel from the camera, each segment L∞
GPU_CONST HG_LOD_CAMERA = 2u;        // L∞ distance from the camera, as for a primary vertex

struct HgAccum {
  uint64_t r, g, b;   // Σ radiance (after the outlier clamp) · radianceScale · HG_FIXED_POINT_SCALE
  uint64_t tr, tg, tb;// Σ what the clamp took off (the tail), same units
  uint64_t lum2;      // Σ (unclamped luminance · radianceScale)² · HG_FIXED_POINT_SCALE (the clamp's σ).
                      // A free slot sums nothing: with deferred claims (HgPush::deferredClaims) it holds the
                      // largest bid for the slot this frame, priority << 32 | key (0 = none; hgInsertOrFind)
  // The samples they sum are in HG_BINDING_COUNTS.
};
GPU_ASSERT_SIZE(HgAccum, 56);

// The outlier clamp keeps the light it takes: the tail is averaged over this
// many times the mean's history, so a firefly's energy arrives spread thinly
// over many frames instead of as a blotch in one.
#define HG_TAIL_HISTORY 16.0
// The clamp needs this many samples behind a cell's mean and σ before it acts:
// a younger cell holds its samples as they came, fireflies included.
#define HG_CLAMP_MIN_SAMPLES 8u
// A pixel whose own cell is younger than that reads, among this many more
// jitters of its surface, the cell with the most samples (hpsf_lookup.comp).
#define HG_LOOKUP_RETRIES 3u

struct HgCell {
  vec3 mean;          // resolved mean demodulated radiance of the clamped samples
  float lumMoment2;   // resolved mean of luminance², of the samples before the outlier clamp
  vec3 tail;          // resolved mean of what the clamp took off (HG_TAIL_HISTORY): the cell's radiance
                      // is mean + tail
  float frames;       // frames of history behind the mean (capped)
  uint recent;        // nhpsf/anhpsf: the mean over the last historySamples samples only; what the
                      // map passes on to the vertices before this one (recent + tail). RGB9E5 of
                      // radiance · radianceScale (up to 65408 × SceneDesc::typicalRadiance), rounded
                      // stochastically (hpsf.glsl's hgPackRecent): each store within a step (0.4% of its
                      // largest channel) and right on average, so frames that move it less than a step
                      // still move it; 8 bytes fewer a cell than three floats (4.2 MB at 2^19 cells)
  uint lastSeen;      // frame index of the last update
  // Aging: the sentinel that detects stale radiance. A ray from the cell's first
  // vertex; re-traced with the same random numbers it gives the same hit
  // distance and the same light at the hit unless the scene moved.
  vec3 sentinelOrigin;
  uint sentinelSeen;       // what it saw (hpsf.glsl's hgPackSentinelSeen), two half floats: the hit
                           // distance in metres (< 0: the ray missed), and the luminance of the light (NEE) at
                           // the hit · radianceScale; 0: no sentinel. 4 bytes fewer a cell than two floats
  uint sentinelDirection;  // octahedral, 2 × 16-bit snorm (hgPackDirection); traced as it unpacks, both times
  uint samples;         // samples behind the mean (capped with the history)
  uint previousLod;     // bits 0–23, strict: global slot + 1 of the same key in the previous frame's
                        // table, 0 = none; bits 24–31: the cell's level of detail + 128 (hgPackPreviousLod)
};
GPU_ASSERT_SIZE(HgCell, 68);

// HgCell::previousLod. Slots stay below 2^23 (two tables of at most 2^21 cells).
GPU_FN uint hgPackPreviousLod(uint previous, int lod) {
  const int biased = lod + 128;
  return (previous & 0xffffffu) | (uint(biased < 0 ? 0 : biased > 255 ? 255 : biased) << 24u);
}
GPU_FN uint hgCellPrevious(uint previousLod) { return previousLod & 0xffffffu; }
GPU_FN int hgCellLod(uint previousLod) { return int(previousLod >> 24u) - 128; }

struct HgTelemetry {
  uint occupied;      // live cells after resolve
  uint failedInserts; // samples that found no free slot in the probe window
  uint probeSum;      // Σ probe lengths of successful inserts
  uint probeMax;      // longest probe
  uint inserts;       // successful inserts (samples stored)
  uint evicted;       // cells removed by the eviction policy this frame
  uint overflows;     // samples clamped to HG_MAX_SAMPLE
  uint staleResets;   // cells whose sentinel came back different enough to cut their history
  uint64_t transported; // anhpsf: Σ luminance added by continuation segments · radianceScale · HG_FIXED_POINT_SCALE
  uint continued;     // anhpsf: pixels with a live continued path after this frame
  uint depthSum;      // anhpsf: Σ of their depths (segments)
  uint reads;         // nhpsf/anhpsf: last frame's map read at a path's scatter vertex
  uint readMisses;    // of those, reads that found no cell (or one without samples): that light is missing
  uint outOfBounds;   // ModuleDesc::checkBounds: indices outside the map's arrays (bounds.glsl)
  uint claimed;       // deferred claims: cells made this frame for the keys that asked (hpsf_claim.comp)
};
GPU_ASSERT_SIZE(HgTelemetry, 64);

// A path walked segment by segment (nhpsf within a frame, anhpsf one segment
// per frame): where it goes next, and the cell its radiance feeds. The
// throughput since that cell is 1 after a diffuse vertex (radiance is
// demodulated) and picks up BSDF weights through glossy vertices.
struct HgWalk {
  vec3 origin;        // next ray's origin (already offset from the surface)
  uint index;         // the fed cell's index hash
  vec3 throughput;
  uint key;           // the fed cell's verification key; HG_EMPTY_KEY = feeds no cell
  uint direction;     // next ray's direction, octahedral, 2 × 16-bit snorm (hgPackDirection)
  float travel;       // metres: the path's travel before the next vertex that sets that vertex's LOD
                      // (HgPush::secondaryLod: unfiltered travel, whole path, or unused)
  uint state;         // bits 0–15: vertices reached (1 = at the primary hit, no segment yet; 0 = no
                      // live path); bit 16: the next segment continues a sample already counted
                      // (after a glossy vertex); bits 24–31: the fed cell's level of detail + 128
  uint pad0;
};
GPU_ASSERT_SIZE(HgWalk, 48);

// A walk as anhpsf keeps it between frames, one per pixel (hpsf.glsl's hgPackWalk, hgUnpackWalk), in
// 28 bytes (issue 30's memory: 58.1 MB at 1920×1080): the origin and the fed cell's key as they are; the
// fed cell's index hash only to the map's largest capacity (the probes read index mod capacity, a power of
// two up to 2^21, so these bits are all of it); the direction octahedral in 2 × 13-bit snorm (within
// 0.03°); the throughput (1 after a diffuse vertex, a BSDF weight after glossy ones) in 7-bit mantissas
// under a shared 5-bit exponent (within 0.8% of its largest channel, 1 exactly); the travel, which only
// the travel-based secondary LODs read, an unsigned 11-bit float (B10G11R11's: within 0.9%); the state
// (vertices reached ≤ 31, the continue flag, the fed cell's level of detail in [-32, 31]).
GPU_CONST HG_WALK_INDEX_BITS = 21u;
struct HgWalkRecord {
  vec3 origin;
  uint key;
  uint directionLod;      // bits 0–25: the direction, 2 × 13-bit snorm; 26–31: LOD + 32
  uint throughputState;   // bits 0–25: the throughput, RGB7E5; 26–30: vertices reached; 31: continues
  uint indexTravel;       // bits 0–20: the index hash mod 2^21; 21–31: the travel (unsigned 11-bit float)
};
GPU_ASSERT_SIZE(HgWalkRecord, 28);

GPU_FN uint hgHashPcg(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Murmur3's finaliser: a hash unrelated to PCG, for the verification key.
GPU_FN uint hgHashMurmur(uint h) {
  h ^= h >> 16u;
  h *= 0x85ebca6bu;
  h ^= h >> 13u;
  h *= 0xc2b2ae35u;
  h ^= h >> 16u;
  return h;
}

// A cell: integer coordinates at a level of detail plus quantised normal bits.
struct HgDescriptor {
  int x, y, z;
  int lod;
  uint normalBits;
};

GPU_FN uint hgIndexHash(HgDescriptor d) {
  uint h = hgHashPcg(uint(d.x));
  h = hgHashPcg(h ^ uint(d.y));
  h = hgHashPcg(h ^ uint(d.z));
  h = hgHashPcg(h ^ uint(d.lod));
  return hgHashPcg(h ^ d.normalBits);
}

GPU_FN uint hgVerificationKey(HgDescriptor d) {
  uint h = hgHashMurmur(uint(d.x) + 0x9e3779b9u);
  h = hgHashMurmur(h ^ (uint(d.y) + 0x7f4a7c15u));
  h = hgHashMurmur(h ^ (uint(d.z) + 0x94d049bbu));
  h = hgHashMurmur(h ^ (uint(d.lod) + 0x2545f491u));
  return hgHashMurmur(h ^ d.normalBits) | 1u;  // never HG_EMPTY_KEY
}

// Cell size (log2, metres) from Alg. 3: the world footprint of a filter
// `footprint` metres wide per metre of travel (filter width in pixels × the
// pixel's angle) after `travel` metres of path, rounded down to a power of
// two (the float's exponent). `u` in [0,1) picks between the two nearest
// powers of two in proportion (stochastic LOD; u = 0 always takes the lower
// one, as in the thesis).
GPU_FN int hgLod(float footprint, float travel, float u) {
  float w = max(footprint * travel, 1e-30f);
  float l = log2(w);
  float lo = floor(l);
  return int(lo) + ((l - lo) > u && u > 0.0f ? 1 : 0);
}

// Alg. 3's travel of a segment: its L∞ length (the largest coordinate difference).
GPU_FN float hgLinf(vec3 from, vec3 to) {
  vec3 d = abs(to - from);
  return max(d.x, max(d.y, d.z));
}

// The smallest LOD whose coordinates stay below HG_COORD_LIMIT at |p|.
GPU_FN int hgMinLodFor(float maxAbsCoordinate) {
  return int(ceil(log2(max(maxAbsCoordinate, 1e-30f) / float(HG_COORD_LIMIT)))) + 1;
}

#define HG_MAX_NORMAL_BITS 6u  // 64 normal bins

// The normal in the frame the bins are cut in: a fixed rotation (the
// quaternion (1, 5, 4, 3)/√51, found by a search over small integer
// quaternions) that keeps every world axis, the normal of an axis-aligned
// wall, at least a tenth of a bin's angular width away from any bin edge for
// every bit count (tests/hash_grid_math_test.cpp). Unrotated,
// bins split at component 0, exactly where those normals lie, so one wall's
// samples would scatter over two or four bins.
GPU_FN vec3 hgNormalFrame(vec3 n) {
  return vec3(dot(vec3(1.0f, 34.0f, -38.0f), n), dot(vec3(46.0f, -17.0f, -14.0f), n), dot(vec3(-22.0f, -34.0f, -31.0f), n)) *
         (1.0f / 51.0f);
}

// Normal bins (Meijer §4.2.2): b bits give 2^b bins in all. One bit is the
// hemisphere (sign of the rotated z); the other b − 1 cut the hemisphere's
// square map (s, t) = (x + y, x − y) / (|x| + |y| + |z|) ∈ [−1, 1]² into a
// 2^⌈(b−1)/2⌉ × 2^⌊(b−1)/2⌋ grid. The result carries b in bits 28–31 so
// different bit counts never share a key.
GPU_FN uint hgNormalBits(vec3 n, uint bits) {
  if (bits == 0u) return 0u;
  vec3 r = hgNormalFrame(n);
  float l1 = max(abs(r.x) + abs(r.y) + abs(r.z), 1e-30f);
  float s = (r.x + r.y) / l1, t = (r.x - r.y) / l1;
  uint sBits = bits / 2u, tBits = (bits - 1u) / 2u;
  float sLevels = float(1u << sBits), tLevels = float(1u << tBits);
  uint qs = uint(clamp((s * 0.5f + 0.5f) * sLevels, 0.0f, sLevels - 1.0f));
  uint qt = uint(clamp((t * 0.5f + 0.5f) * tLevels, 0.0f, tLevels - 1.0f));
  uint hemisphere = r.z >= 0.0f ? 1u : 0u;
  return (hemisphere << (bits - 1u)) | (qs << tBits) | qt | (bits << 28u);
}

// An orthonormal tangent basis of n.
GPU_FN void hgTangents(vec3 n, GPU_OUT(vec3) t, GPU_OUT(vec3) b) {
  vec3 a = abs(n.x) > 0.9f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
  t = normalize(cross(n, a));
  b = cross(n, t);
}

// Position jitter (Alg. 3): δ uniform in [−1, 1]³ (from u in [0,1)³) with its
// normal component removed, times jitter × cell size: ±jitter cells in the
// tangent plane, zero mean.
GPU_FN vec3 hgJitter(vec3 n, vec3 u, float jitter, float cellSize) {
  vec3 delta = u * 2.0f - vec3(1.0f);
  delta -= n * dot(n, delta);
  return delta * (jitter * cellSize);
}

// Normal jitter (Meijer Figs. 11c, 14c): the normal tilted by up to ±jitter
// bin widths along each tangent (a bin of 2^b spans about √(4π / 2^b)
// radians), so samples near a bin edge spread over both sides of it.
GPU_FN vec3 hgJitterNormal(vec3 n, vec2 u, float jitter, uint bits) {
  if (bits == 0u || jitter <= 0.0f) return n;
  vec3 t, b;
  hgTangents(n, t, b);
  float width = sqrt(4.0f * 3.14159265f / float(1u << bits));
  vec2 delta = (u * 2.0f - vec2(1.0f)) * (jitter * width);
  return normalize(n + t * delta.x + b * delta.y);
}

// Quantises p (already jittered) at `lod`, raised if needed so no coordinate overflows.
GPU_FN HgDescriptor hgDescriptor(vec3 p, vec3 n, int lod, uint normalBitCount) {
  float m = max(abs(p.x), max(abs(p.y), abs(p.z)));
  HgDescriptor d;
  d.lod = max(lod, hgMinLodFor(m));
  float inv = exp2(-float(d.lod));
  d.x = int(floor(p.x * inv));
  d.y = int(floor(p.y * inv));
  d.z = int(floor(p.z * inv));
  d.normalBits = hgNormalBits(n, normalBitCount);
  return d;
}

// Fixed point makes the sums order-independent: lavapipe and a GPU, or two
// runs with different thread timing, add up to the same bits.
GPU_FN uint64_t hgToFixed(float v) { return uint64_t(clamp(v, 0.0f, float(HG_MAX_SAMPLE)) * float(HG_FIXED_POINT_SCALE)); }
GPU_FN float hgFromFixed(uint64_t v, uint count) { return float(v) / float(HG_FIXED_POINT_SCALE) / float(max(count, 1u)); }

struct HgPush {
  uint capacity;          // power of two
  uint probeWindow;       // linear probing limit, slots
  float filterWidth;      // pixels
  float pixelAngle;       // metres per metre of distance per pixel
  float jitter;           // ± cells in the tangent plane, 0 = off
  uint normalBits;        // 2^b normal bins in all, 0–HG_MAX_NORMAL_BITS
  uint stochasticLod;     // 1: choose between the two nearest levels at random
  float clampSigma;       // k: samples above mean + k·σ are clamped (0 = off)
  uint frameIndex;
  uint historyCap;        // frames of history a cell keeps
  uint staleFrames;       // cells untouched this long are evicted
  uint minSamples;        // below this a pixel falls back to its own sample
  uint seed;
  uint samplesPerPixel;
  uint maxBounces;
  uint russianRouletteStart;
  uint table;             // first slot of the table written this frame
  uint previousTable;     // strict: first slot of the previous frame's table (= table with aging)
  uint strict;            // 1: two swapped tables, a cell's mean is this frame's and the last frame's samples
  uint debugView;         // GI_DEBUG_*: the lookup measures probe-window occupancy only for its view
  uint mode;              // HG_MODE_*
  uint depth;             // nhpsf: segments per frame; anhpsf: the longest continued path
  float secondaryWidthScale; // cells at vertices after the first are this much wider
  uint validationInterval;  // aging: frames between re-traces of a cell's sentinel (0 = off)
  float radianceScale;    // 1 / SceneDesc::typicalRadiance: radiance is summed as radiance · radianceScale in fixed point
  uint forgetLight;       // 1 in the frame after gi::invalidate(LightsChanged): every cell's mean restarts
  float normalJitter;     // ± normal bins, 0 = off
  uint secondaryLod;      // HG_LOD_*: the travel that sets the LOD at vertices after the first
  uint historySamples;    // aging, nhpsf/anhpsf: samples behind a cell's `recent` mean (0 = its whole history)
  uint deferredClaims;    // aging, 1: a missing key asks for a slot and gets it after the inserts (hgInsertOrFind)
  uint pad1;
  uint pad2;
};
GPU_ASSERT_SIZE(HgPush, 128);

GPU_NAMESPACE_END
#endif
