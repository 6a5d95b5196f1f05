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
GPU_CONST HG_BINDING_PIXEL_CELL = 4; // r32ui image: cell index + 1 per pixel, 0 = none
GPU_CONST HG_BINDING_CONTINUATION = 5; // HgWalk[pixels]: anhpsf's paths continued over frames

GPU_CONST HG_MODE_HPSF = 0u;         // full paths from the primary hit; the primary cell filters
GPU_CONST HG_MODE_NHPSF = 1u;        // pathDepth segments; every diffuse vertex's cell filters
GPU_CONST HG_MODE_ANHPSF = 2u;       // one primary segment + one continued segment per pixel and frame

struct HgAccum {
  uint64_t r, g, b;   // Σ radiance · radianceScale · HG_FIXED_POINT_SCALE
  uint64_t lum2;      // Σ (unclamped luminance · radianceScale)² · HG_FIXED_POINT_SCALE (the clamp's σ)
  uint count;         // samples this frame
  uint pad0;
};

struct HgCell {
  vec3 mean;          // resolved mean demodulated radiance
  float lumMoment2;   // resolved mean of luminance², of the samples before the outlier clamp
  float frames;       // frames of history behind the mean (capped)
  uint lastSeen;      // frame index of the last update
  int lod;            // the cell's level of detail (log2 of its size)
  uint samples;       // samples behind the mean (capped with the history)
  uint previous;      // strict: global slot + 1 of the same key in the previous frame's table, 0 = none
  // Aging: the probe that detects stale radiance. A ray from the cell's first
  // vertex; re-traced with the same random numbers it gives the same hit
  // distance and the same light at the hit unless the scene moved.
  vec3 probeOrigin;
  float probeDistance;  // metres; < 0: the ray missed; 0 with probeLight 0: no probe
  vec3 probeDirection;
  float probeLight;     // luminance of the light (NEE) at the hit
};

struct HgTelemetry {
  uint occupied;      // live cells after resolve
  uint failedInserts; // samples that found no free slot in the probe window
  uint probeSum;      // Σ probe lengths of successful inserts
  uint probeMax;      // longest probe
  uint inserts;       // successful inserts (samples stored)
  uint evicted;       // cells removed by the eviction policy this frame
  uint overflows;     // samples clamped to HG_MAX_SAMPLE
  uint staleResets;   // cells whose probe came back different enough to cut their history
  uint64_t transported; // anhpsf: Σ luminance added by continuation segments · radianceScale · HG_FIXED_POINT_SCALE
  uint continued;     // anhpsf: pixels with a live continued path after this frame
  uint depthSum;      // anhpsf: Σ of their depths
};
GPU_ASSERT_SIZE(HgTelemetry, 48);

// A path walked segment by segment (nhpsf within a frame, anhpsf one segment
// per frame): where it goes next, and the cell its radiance feeds. The
// throughput since that cell is 1 after a diffuse vertex (radiance is
// demodulated) and picks up BSDF weights through glossy vertices.
struct HgWalk {
  vec3 origin;        // next ray's origin (already offset from the surface)
  uint index;         // the fed cell's index hash
  vec3 direction;
  uint key;           // the fed cell's verification key; HG_EMPTY_KEY = feeds no cell
  vec3 throughput;
  uint state;         // bits 0–15: segments taken, 0 = no live path; bit 16: the next segment
                      // continues a sample already counted (after a glossy vertex); bits 24–31: the
                      // fed cell's level of detail + 128 (for the debug views)
};
GPU_ASSERT_SIZE(HgWalk, 48);

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

// Cell size (log2, metres) from Alg. 3: the world footprint of `filterWidth`
// pixels at `travel` metres from the camera, where a pixel spans
// `pixelAngle` metres per metre of distance. `u` in [0,1) picks between the
// two nearest powers of two in proportion (stochastic LOD; u = 0 always takes
// the lower one, as in the thesis).
GPU_FN int hgLod(float filterWidth, float pixelAngle, float travel, float u) {
  float w = max(filterWidth * pixelAngle * travel, 1e-30f);
  float l = log2(w);
  float lo = floor(l);
  return int(lo) + ((l - lo) > u && u > 0.0f ? 1 : 0);
}

// The smallest LOD whose coordinates stay below HG_COORD_LIMIT at |p|.
GPU_FN int hgMinLodFor(float maxAbsCoordinate) {
  return int(ceil(log2(max(maxAbsCoordinate, 1e-30f) / float(HG_COORD_LIMIT)))) + 1;
}

GPU_FN uint hgNormalBits(vec3 n, uint bits) {
  if (bits == 0u) return 0u;
  float levels = float(1u << bits);
  uint qx = uint(clamp((n.x * 0.5f + 0.5f) * levels, 0.0f, levels - 1.0f));
  uint qy = uint(clamp((n.y * 0.5f + 0.5f) * levels, 0.0f, levels - 1.0f));
  uint qz = uint(clamp((n.z * 0.5f + 0.5f) * levels, 0.0f, levels - 1.0f));
  return (qx << (2u * bits)) | (qy << bits) | qz | (bits << 28u);
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

// Offset in the tangent plane of n: (u − 0.5, v − 0.5) · jitter · cell size.
// Zero mean, orthogonal to n.
GPU_FN vec3 hgJitter(vec3 n, vec2 uv, float jitter, float cellSize) {
  vec3 a = abs(n.x) > 0.9f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t = normalize(cross(n, a));
  vec3 b = cross(n, t);
  return (t * (uv.x - 0.5f) + b * (uv.y - 0.5f)) * (jitter * cellSize);
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
  float jitter;           // fraction of a cell, 0 = off
  uint normalBits;        // 0–3 bits per normal component
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
  uint validationInterval;  // aging: frames between re-traces of a cell's probe (0 = off)
  float radianceScale;    // 1 / SceneDesc::typicalRadiance: radiance is summed as radiance · radianceScale in fixed point
  uint forgetLight;       // 1 in the frame after gi::invalidate(LightsChanged): every cell's mean restarts
  uint pad1;
  uint pad2;
};
GPU_ASSERT_SIZE(HgPush, 112);

GPU_NAMESPACE_END
#endif
