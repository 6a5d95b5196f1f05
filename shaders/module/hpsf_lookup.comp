#version 460
// Hashed path space filtering, lookup (Meijer Alg. 5): each pixel reads the
// resolved mean of its own cell, or keeps its own sample when the cell is
// missing or holds too few samples. Leaves the hash debug views' data in giDebug
// when a debug view is on.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf_walk.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

// The pixel's cell, found again as the insert made it: the same surface, the
// same random numbers (GI_STREAM_HASH of this frame), so the same key; the
// global slot + 1, 0 = none. Recomputing costs a few hashes and one probe
// walk, where keeping it costs an r32ui image the size of the render
// (8.3 MB at 1080p, a twentieth of hpsf's memory).
//
// When that cell holds fewer samples than the outlier clamp needs, its mean is
// a few samples as they came, and one may be a firefly: with strict eviction a
// cell that no pixel's jitter reached for one frame starts over, and a sliver
// of a cell that one pixel alone reached holds that pixel's path and nothing
// else (Cornell, 64×48: single pixels with 0.5 of squared error, frames at
// 2.6× their neighbours' error). The pixel then reads, among HG_LOOKUP_RETRIES
// more jitters of its surface (the next random numbers of the same stream),
// the cell with the most samples: the jitter's stochastic blend of
// neighbouring cells, drawn again. With aging such cells are rare once the map
// has filled (a cell lives on through frames nobody touches it).
uint hgPixelCell(ivec2 p) {
  if (!giGbCovered(p)) return 0u;
  vec3 V;
  const GiSurface s = giGbSurface(p, V);
  if (!giHasDiffuseLobe(s.material)) return 0u;
  GiRng rng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
  const HgDescriptor d = hgPrimaryDescriptor(s.position, s.normal, rng);
  int best = hgFind(pc.table, hgIndexHash(d), hgVerificationKey(d), pc.capacity, pc.probeWindow);
  uint bestSamples = best >= 0 ? HG_AT(hgCells, best).samples : 0u;
  for (uint retry = 0u; retry < HG_LOOKUP_RETRIES && best >= 0 && bestSamples < HG_CLAMP_MIN_SAMPLES; ++retry) {
    const HgDescriptor other = hgPrimaryDescriptor(s.position, s.normal, rng);
    const int slot = hgFind(pc.table, hgIndexHash(other), hgVerificationKey(other), pc.capacity, pc.probeWindow);
    if (slot >= 0 && HG_AT(hgCells, slot).samples > bestSamples && HG_AT(hgCells, slot).frames > 0.0) {
      best = slot;
      bestSamples = HG_AT(hgCells, slot).samples;
    }
  }
  return best >= 0 ? uint(best) + 1u : 0u;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  vec3 result = giLoadNoisy(p);
  uint cell = hgPixelCell(p);
  vec4 debug = vec4(0.0);
  if (cell > 0u) {
    HgCell c = HG_AT(hgCells, cell - 1u);
    if (c.samples >= pc.minSamples && c.frames > 0.0) result = hgCellRadiance(c);
    uint key = HG_AT(hgKeys, cell - 1u);
    // Debug: cell colour from its key, LOD, samples, and whether the cell was used.
    debug = vec4(float(key & 0xffffffu), float(hgCellLod(c.previousLod)), float(c.samples), c.samples >= pc.minSamples ? 1.0 : 0.5);
  }
  if (pc.debugView == GI_DEBUG_HASH_OCCUPANCY) {
    // Occupied share of the probe window starting at the pixel's cell: where
    // it nears 1, inserts there are about to fail. No cell: the window was full.
    float used = float(pc.probeWindow);
    if (cell > 0u) {
      uint table = (cell - 1u) - (cell - 1u) % pc.capacity;
      used = 0.0;
      for (uint i = 0u; i < pc.probeWindow; ++i)
        used += HG_AT(hgKeys, table + ((cell - 1u + i) & (pc.capacity - 1u))) != HG_EMPTY_KEY ? 1.0 : 0.0;
    }
    debug.w = used / float(pc.probeWindow);
  }
  if (pc.debugView == GI_DEBUG_CONTINUATION_DEPTH && pc.mode == HG_MODE_ANHPSF) {
    debug.x = float(hgWalkSegments(hgUnpackWalk(HG_AT(hgWalks, uint(p.y) * giFrame.size.x + uint(p.x))))) / float(pc.depth);
  }
  giStoreIndirect(p, result);
  // The debug image exists at full size only while a debug view is on (the module allocates it then).
  if (pc.debugView != GI_DEBUG_NONE) imageStore(giDebug, p, debug);
}
