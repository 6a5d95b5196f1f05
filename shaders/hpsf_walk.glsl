// The pieces every hash-map path pass shares: a vertex's cell, adding a
// sample to it (with the outlier clamp and telemetry), reading last frame's
// mean, and one segment of a filtered path (nhpsf, anhpsf).
//
// What a cell holds: the demodulated indirect radiance arriving at its
// vertices, i.e. light that has left another surface by reflection (emitters
// seen along the segment are that vertex's direct light, not counted here).
// A segment from v to w therefore brings NEE at w plus w's diffuse albedo
// times w's own cell, read from last frame's map: repeated over frames, the
// cells converge to every bounce, not only those traced this frame.
#ifndef GI_HPSF_WALK_GLSL
#define GI_HPSF_WALK_GLSL
#include "path.glsl"
#include "gi_frame.glsl"
#include "hpsf.glsl"
#include "hpsf_probe.glsl"

layout(push_constant, scalar) uniform Push { HgPush pc; };

// This invocation's telemetry, flushed once per subgroup by hgFlushTelemetry.
uint hgProbeCount = 0u, hgProbeMax = 0u, hgFailedCount = 0u, hgInsertedCount = 0u, hgOverflowCount = 0u;
float hgTransported = 0.0;

// The cell of a vertex: level of detail from its distance to the camera and
// the filter width (× widthScale for vertices after the first), then jittered
// in the tangent plane and quantised (Meijer Alg. 3).
HgDescriptor hgVertexDescriptor(vec3 position, vec3 normal, float widthScale, inout GiRng rng) {
  float travel = distance(giFrame.camera.position, position);
  int lod = hgLod(pc.filterWidth * widthScale, pc.pixelAngle, travel, pc.stochasticLod != 0u ? giRandom(rng) : 0.0);
  vec3 jittered = position + hgJitter(normal, giRandom2(rng), pc.jitter, exp2(float(lod)));
  return hgDescriptor(jittered, normal, lod, pc.normalBits);
}

// The table holding last frame's resolved means: the other table with strict
// eviction; the one table with aging (resolve has not run yet this frame).
uint hgReadTable() { return pc.strict != 0u ? pc.previousTable : pc.table; }

// Adds a sample (count = 1 for a new sample, 0 for more light on one already
// counted) to the cell (index, key) of this frame's table. Samples above the
// cell's history mean + kσ of luminance are clamped so one firefly cannot
// poison the cache. The invocation that makes the cell stores its stale-radiance
// probe: the ray (probeOrigin, probeDirection) from the vertex, and what it sees.
// Returns the global slot, or -1 when the probe window is full.
int hgInsertSample(uint index, uint key, vec3 radiance, uint count, int lod, vec3 probeOrigin, vec3 probeDirection) {
  uint probes;
  bool created;
  int slot = hgInsertOrFind(pc.table, index, key, pc.capacity, pc.probeWindow, probes, created);
  if (slot < 0) {
    hgFailedCount++;
    return -1;
  }
  if (created && pc.validationInterval > 0u) {
    float distance_, light;
    hgTraceProbe(probeOrigin, probeDirection, key, distance_, light);
    hgCells[slot].probeOrigin = probeOrigin;
    hgCells[slot].probeDirection = probeDirection;
    hgCells[slot].probeDistance = distance_;
    hgCells[slot].probeLight = light;
  }
  hgProbeCount += probes;
  hgProbeMax = max(hgProbeMax, probes);
  // With strict eviction the history is the same key's cell in the previous
  // frame's table, which this cell links to and keeps alive.
  HgCell history = hgCells[slot];
  if (pc.strict != 0u) {
    int previous = hgFind(pc.previousTable, index, key, pc.capacity, pc.probeWindow);
    if (previous >= 0) {
      history = hgCells[previous];
      hgCells[slot].previous = uint(previous) + 1u;  // every writer of this key writes the same value
      hgCells[previous].lastSeen = pc.frameIndex;
    }
  }
  // The clamp's σ comes from the second moment of the samples as they
  // arrived, before clamping: a limit computed from clamped samples chases
  // itself down frame after frame (on Conference hpsf lost 15% of its
  // indirect light over 64 frames that way, and kept falling). The mean is
  // the cell's clamped one, which only makes σ larger: a more lenient clamp.
  vec3 sample_ = radiance;
  float lum = giLuminance(sample_);
  if (pc.clampSigma > 0.0 && history.samples >= 8u) {
    // Never below twice the mean: where samples barely vary (σ ≈ 0), a cell
    // whose light is still building up over frames (nhpsf, anhpsf) must be
    // able to rise; fireflies are far above that.
    float mean = giLuminance(history.mean);
    float sigma = sqrt(max(history.lumMoment2 - mean * mean, 0.0));
    float limit = max(mean + pc.clampSigma * sigma, 2.0 * mean);
    if (lum > limit && lum > 0.0) sample_ *= limit / lum;
  }
  bool overflowed = false;
  hgAccumulate(slot, sample_ * pc.radianceScale, lum * pc.radianceScale, count, overflowed);
  if (overflowed) hgOverflowCount++;
  hgCells[slot].lod = lod;  // every writer of this key writes the same value
  hgInsertedCount++;
  return slot;
}

// Last frame's mean at (index, key); false when the cell is missing or holds too few samples.
bool hgReadCell(uint index, uint key, out vec3 mean) {
  mean = vec3(0.0);
  int slot = hgFind(hgReadTable(), index, key, pc.capacity, pc.probeWindow);
  if (slot < 0) return false;
  HgCell c = hgCells[slot];
  if (c.samples < pc.minSamples || c.frames == 0.0) return false;
  mean = c.mean;
  return true;
}

// A walk that starts at a diffuse vertex s: a cosine direction, feeding s's
// cell (primary: the filter width; later vertices: × secondaryWidthScale).
uint hgWalkState(uint depth, bool continues, int lod) {
  return (depth & 0xffffu) | (continues ? 0x10000u : 0u) | (uint(clamp(lod + 128, 0, 255)) << 24u);
}
uint hgWalkDepth(HgWalk w) { return w.state & 0xffffu; }
bool hgWalkContinues(HgWalk w) { return (w.state & 0x10000u) != 0u; }
int hgWalkLod(HgWalk w) { return int(w.state >> 24u) - 128; }

HgWalk hgWalkFrom(GiSurface s, HgDescriptor d, bool feeds, uint depth, inout GiRng rng) {
  HgWalk w;
  w.origin = giOffsetRay(s.position, s.geometricNormal);
  w.direction = giCosineSample(s.normal, giRandom2(rng));
  w.index = hgIndexHash(d);
  w.key = feeds ? hgVerificationKey(d) : HG_EMPTY_KEY;
  w.throughput = vec3(1.0);
  w.state = hgWalkState(depth, false, d.lod);
  return w;
}

// One segment: traces the walk's ray to w, adds what arrives (× throughput)
// to the cell it feeds, and moves the walk on. A diffuse w starts feeding its
// own cell; a glossy w passes on with its BSDF weight, still feeding the same
// cell; a miss ends the walk (after counting its zero sample). Returns the
// radiance arriving at the walk's vertex (before throughput).
vec3 hgStep(inout HgWalk walk, inout GiRng rng) {
  vec3 arriving = vec3(0.0);
  GiHit hit = giTraceClosest(walk.origin, walk.direction, 0.0, GI_FLT_MAX);
  GiSurface w;
  GiBsdf b;
  HgDescriptor dw;
  bool diffuse = false;
  if (hit.t >= 0.0) {
    w = giSurfaceFromHit(hit, walk.direction);
    b = giMakeBsdf(w.material.baseColor, w.material.metallic, w.material.roughness, w.material.flags);
    arriving = giDirectLight(w, b, -walk.direction, false, rng);  // NEE alone: no emitter is hit after w
    diffuse = (w.material.flags & MATERIAL_FLAG_GLOSSY) == 0u;
    if (diffuse) {
      dw = hgVertexDescriptor(w.position, w.normal, pc.secondaryWidthScale, rng);
      vec3 cell;
      if (hgReadCell(hgIndexHash(dw), hgVerificationKey(dw), cell)) arriving += b.diffuse * cell;
    }
    if (!giKeepSample(arriving, vec3(0.0))) arriving = vec3(0.0);
  }
  if (walk.key != HG_EMPTY_KEY) {
    vec3 added = walk.throughput * arriving;
    hgInsertSample(walk.index, walk.key, added, hgWalkContinues(walk) ? 0u : 1u, hgWalkLod(walk), walk.origin,
                   walk.direction);
    if (pc.mode == HG_MODE_ANHPSF && hgWalkDepth(walk) > 1u) hgTransported += giLuminance(added);
  }
  uint depth = hgWalkDepth(walk) + 1u;
  if (hit.t < 0.0) {
    walk.state = 0u;
  } else if (diffuse) {
    walk = hgWalkFrom(w, dw, true, depth, rng);
  } else {
    // Glossy: sample its BSDF and keep feeding the same cell; what arrives next continues this sample.
    vec3 L, weight;
    float pdf;
    vec3 u = vec3(giRandom2(rng), giRandom(rng));
    if (!giBsdfSample(b, w.normal, -walk.direction, u, L, weight, pdf) || dot(L, w.geometricNormal) <= 0.0) {
      walk.state = 0u;
    } else {
      walk.origin = giOffsetRay(w.position, w.geometricNormal);
      walk.direction = L;
      walk.throughput *= weight;
      walk.state = hgWalkState(depth, true, hgWalkLod(walk));
    }
  }
  return arriving;
}

// Adds this invocation's telemetry to the frame's, one atomic per subgroup and counter.
void hgFlushTelemetry() {
  uint sumInserted = subgroupAdd(hgInsertedCount), sumFailed = subgroupAdd(hgFailedCount);
  uint sumProbes = subgroupAdd(hgProbeCount), maxProbes = subgroupMax(hgProbeMax);
  uint sumOverflow = subgroupAdd(hgOverflowCount);
  float transported = subgroupAdd(hgTransported);
  if (subgroupElect()) {
    if (sumInserted > 0u) atomicAdd(hgTelemetry.inserts, sumInserted);
    if (sumFailed > 0u) atomicAdd(hgTelemetry.failedInserts, sumFailed);
    if (sumProbes > 0u) atomicAdd(hgTelemetry.probeSum, sumProbes);
    if (maxProbes > 0u) atomicMax(hgTelemetry.probeMax, maxProbes);
    if (sumOverflow > 0u) atomicAdd(hgTelemetry.overflows, sumOverflow);
    if (transported > 0.0) atomicAdd(hgTelemetry.transported, hgToFixed(transported * pc.radianceScale));
  }
}

#endif
