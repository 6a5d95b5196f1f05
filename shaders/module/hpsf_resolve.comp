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

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

// The sums' means: of the clamped samples, of what the clamp took off, of luminance².
vec3 frameMean(HgFrameSums a) {
  return vec3(hgFromFixed(a.sums.r, a.count), hgFromFixed(a.sums.g, a.count), hgFromFixed(a.sums.b, a.count)) / pc.radianceScale;
}
vec3 frameTail(HgFrameSums a) {
  return vec3(hgFromFixed(a.sums.tr, a.count), hgFromFixed(a.sums.tg, a.count), hgFromFixed(a.sums.tb, a.count)) / pc.radianceScale;
}
float frameMoment2(HgFrameSums a) { return hgFromFixed(a.sums.lum2, a.count) / (pc.radianceScale * pc.radianceScale); }

// The recent mean's window in frames: historySamples samples at this frame's count (nhpsf and anhpsf pass it
// on; see resolveAging), at most the mean's own window `cap`.
float recentWindow(uint count, float cap) {
  return pc.historySamples > 0u && count > 0u ? clamp(float(pc.historySamples) / float(count), 1.0, cap) : cap;
}
// The recent mean after this frame's samples `a` (a.count > 0) join the one `frames` frames hold.
uint blendRecent(HgCell c, float frames, HgFrameSums a, float window, uint key) {
  const float w = 1.0 / (min(frames, window - 1.0) + 1.0);
  return hgPackRecent(frames > 0.0 ? mix(hgCellRecent(c, pc.radianceScale), frameMean(a), w) : frameMean(a),
                      pc.radianceScale, key, pc.frameIndex);
}

// Strict eviction (Meijer §4.2.2): the cell's sums are this frame's samples
// plus everything its key held in the last frame's table, written back so
// that the next frame finds them there in turn: a cell touched every frame
// keeps its whole history. Cells of the last frame's table that nobody found
// this frame die with it (its table is cleared before it is written again).
#define HG_STRICT_MAX_COUNT 1073741824u  // 2^30 samples: halve the sums (same mean) before the count could wrap
void resolveStrict(uint i, inout uint live, inout uint evicted) {
  uint slot = pc.table + i;
  if (HG_AT(hgKeys, slot) != HG_EMPTY_KEY) {
    HgFrameSums a = hgLoadFrameSums(slot);
    HgCell c = HG_AT(hgCells, slot);
    const uint key = HG_AT(hgKeys, slot);
    // What nhpsf's vertices read: the whole history's mean would lag behind light that builds up over
    // frames, so, as with aging, a recent mean over historySamples samples, carried from the last table.
    const uint previous = hgCellPrevious(c.previousLod);
    const bool carried = previous > 0u && pc.forgetLight == 0u;
    HgCell last = hgEmptyCell();
    if (carried) last = HG_AT(hgCells, previous - 1u);  // (a ?: of the buffer's and a local struct is bad SPIR-V)
    const float window = recentWindow(a.count, float(pc.historyCap));
    c.recent = a.count > 0u ? blendRecent(last, carried ? last.frames : 0.0, a, window, key) : last.recent;
    c.frames = 1.0;
    if (carried) {
      HgFrameSums b = hgLoadFrameSums(previous - 1u);
      a.sums.r += b.sums.r;
      a.sums.g += b.sums.g;
      a.sums.b += b.sums.b;
      a.sums.tr += b.sums.tr;
      a.sums.tg += b.sums.tg;
      a.sums.tb += b.sums.tb;
      a.sums.lum2 += b.sums.lum2;
      a.count += b.count;
      c.frames = last.frames + 1.0;
    }
    if (a.count >= HG_STRICT_MAX_COUNT) {
      a.sums.r /= 2ul;
      a.sums.g /= 2ul;
      a.sums.b /= 2ul;
      a.sums.tr /= 2ul;
      a.sums.tg /= 2ul;
      a.sums.tb /= 2ul;
      a.sums.lum2 /= 2ul;
      a.count /= 2u;
    }
    hgStoreFrameSums(slot, a);
    c.mean = frameMean(a);  // the whole history's
    c.tail = frameTail(a);
    c.lumMoment2 = frameMoment2(a);
    c.samples = a.count;
    c.lastSeen = pc.frameIndex;
    HG_AT(hgCells, slot) = c;
    live = 1u;
  }
  uint previous = pc.previousTable + i;
  if (HG_AT(hgKeys, previous) != HG_EMPTY_KEY && HG_AT(hgCells, previous).lastSeen != pc.frameIndex) evicted = 1u;
}

// This frame's samples (a.count > 0) into the aging cell's running means: the mean and the luminance moment
// over up to `cap` frames, the recent mean (what the map passes on) over `recentCap`, the clamp's tail over
// HG_TAIL_HISTORY times as many; and the samples behind the mean.
void blendFrameIntoCell(inout HgCell c, HgFrameSums a, float cap, float recentCap, uint key) {
  vec3 frameMean = frameMean(a);
  vec3 frameTail = frameTail(a);
  float frameM2 = frameMoment2(a);
  float w = 1.0 / (min(c.frames, cap - 1.0) + 1.0);
  float wTail = 1.0 / (min(c.frames, cap * HG_TAIL_HISTORY - 1.0) + 1.0);
  c.mean = c.frames > 0.0 ? mix(c.mean, frameMean, w) : frameMean;
  c.recent = blendRecent(c, c.frames, a, recentCap, key);
  c.tail = c.frames > 0.0 ? mix(c.tail, frameTail, wTail) : frameTail;
  c.lumMoment2 = c.frames > 0.0 ? mix(c.lumMoment2, frameM2, w) : frameM2;
  c.frames = min(c.frames + 1.0, float(pc.historyCap) * HG_TAIL_HISTORY);
  // Samples behind the mean: all of them while the mean weighs every frame
  // equally; once the cap turns it into an exponential average, this
  // frame's plus the (1 − w) share of the history it keeps.
  float kept = c.frames <= cap ? 1.0 : 1.0 - w;
  c.samples = a.count + uint(float(c.samples) * kept + 0.5);
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
void resolveAging(uint slot, inout uint live, inout uint evicted) {
  uint key = HG_AT(hgKeys, slot);
  if (key == HG_EMPTY_KEY) return;
  if (key == HG_TOMBSTONE_KEY) {
    hgTidyTombstone(pc.table, slot, pc.capacity);
    return;
  }
  HgFrameSums a = hgLoadFrameSums(slot);
  HgCell c = HG_AT(hgCells, slot);
  // The windows in frames (c.frames counts on, for the tail's longer one).
  // They depend on the sample count only, never on the radiance: a window
  // that followed the cell's own σ/μ would stretch after every bright sample
  // and keep it longer (measured: +7% light on Sponza with hpsf).
  float cap = float(pc.historyCap);
  float recentCap = recentWindow(a.count, cap);
  // Stale radiance: hpsf_validate.comp, before this pass, cut histories the sentinels found stale.
  if (pc.forgetLight != 0u) {
    // The engine says the lights changed: the history goes (hpsf_validate.comp
    // taught every sentinel the new light). The cell keeps its key and its sentinel;
    // until this frame's samples (if any) restart its mean, it is not read.
    c.frames = 0.0;
    c.samples = 0u;
    HG_AT(hgCells, slot) = c;
  }
  if (a.count > 0u) {
    blendFrameIntoCell(c, a, cap, recentCap, key);
    c.lastSeen = pc.frameIndex;
    HG_AT(hgCells, slot) = c;
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
  uint live = 0u, evicted = 0u;
  if (i < pc.capacity) {
    if (pc.strict != 0u) resolveStrict(i, live, evicted);
    else resolveAging(pc.table + i, live, evicted);
  }
  uint sumLive = subgroupAdd(live), sumEvicted = subgroupAdd(evicted);
  if (subgroupElect()) {
    if (sumLive > 0u) atomicAdd(hgTelemetry.occupied, sumLive);
    if (sumEvicted > 0u) atomicAdd(hgTelemetry.evicted, sumEvicted);
  }
}
