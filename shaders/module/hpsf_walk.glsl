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
#include "hpsf_sentinel.glsl"

layout(push_constant, scalar) uniform Push { HgPush pc; };

// This invocation's telemetry, flushed once per subgroup by hgFlushTelemetry.
uint hgProbeCount = 0u, hgProbeMax = 0u, hgFailedCount = 0u, hgInsertedCount = 0u, hgOverflowCount = 0u;
uint hgReadCount = 0u, hgReadMissCount = 0u;
float hgTransported = 0.0;

// The cell of a vertex (Meijer Alg. 3): its level of detail from the filter
// width (× widthScale) and the path's travel to it, `travelBefore` plus the
// L∞ length of the segment from `origin`; the position jittered ±jitter cells
// in the tangent plane; the level of detail computed again at the jittered
// point (the thesis: "if jittering offset is used, filter width becomes
// wrong"); the normal jittered; then quantised.
HgDescriptor hgVertexDescriptor(vec3 position, vec3 normal, vec3 origin, float travelBefore, float widthScale,
                                inout GiRng rng) {
  float footprint = pc.filterWidth * widthScale * pc.pixelAngle;
  float u = pc.stochasticLod != 0u ? giRandom(rng) : 0.0;
  int lod = hgLod(footprint, travelBefore + hgLinf(origin, position), u);
  vec3 jittered = position + hgJitter(normal, vec3(giRandom2(rng), giRandom(rng)), pc.jitter, exp2(float(lod)));
  int jitteredLod = hgLod(footprint, travelBefore + hgLinf(origin, jittered), u);
  vec3 n = hgJitterNormal(normal, giRandom2(rng), pc.normalJitter, pc.normalBits);
  return hgDescriptor(jittered, n, jitteredLod, pc.normalBits);
}

// A primary vertex's cell: its travel is the segment from the camera.
HgDescriptor hgPrimaryDescriptor(vec3 position, vec3 normal, inout GiRng rng) {
  return hgVertexDescriptor(position, normal, giFrame.camera.position, 0.0, 1.0, rng);
}

// The travel a walk leaving the primary vertex carries towards its next
// vertex's level of detail (HgPush::secondaryLod).
float hgPrimaryTravel(vec3 position) {
  return pc.secondaryLod == HG_LOD_PATH ? hgLinf(giFrame.camera.position, position) : 0.0;
}

// The table holding last frame's resolved means: the other table with strict
// eviction; the one table with aging (resolve has not run yet this frame).
uint hgReadTable() { return pc.strict != 0u ? pc.previousTable : pc.table; }

// A bid's priority (deferred claims: hgInsertOrFind): random, and the same every run, since each invocation
// makes the same inserts in the same order.
uint hgBidCount = 0u;
uint hgBidPriority() {
  return hgHashPcg(hgHashPcg(gl_GlobalInvocationID.x ^ hgHashPcg(gl_GlobalInvocationID.y ^ pc.frameIndex)) + hgBidCount++);
}

// Adds a sample (count = 1 for a new sample, 0 for more light on one already
// counted, which only finds the cell) to the cell (index, key) of this frame's table. Samples above the
// cell's history mean + kσ of luminance are clamped so one firefly cannot
// poison the cache. Returns the global slot, or -1 when the probe window is
// full or (deferred claims) the cell is made after this frame's inserts; `needsSentinel` when this
// invocation made the cell, or with deferred claims brings the first sample to a cell without one, and the
// cell keeps a stale-radiance sentinel, which the caller traces (HgSentinel) and stores (hgStoreSentinel).
int hgInsertSample(uint index, uint key, vec3 radiance, uint count, int lod, out bool needsSentinel) {
  uint probes;
  bool created;
  needsSentinel = false;
  // More light for a sample already counted belongs to an existing cell: it never makes one (a cell
  // holding light but no sample would pass that light on to whatever key claims the slot next).
  int slot = hgInsertOrFind(pc.table, index, key, pc.capacity, pc.probeWindow, count > 0u, pc.deferredClaims != 0u,
                            hgBidPriority(), probes, created);
  if (slot == HG_SLOT_ASKED) return -1;
  if (slot < 0) {
    hgFailedCount++;
    return -1;
  }
  hgProbeCount += probes;
  hgProbeMax = max(hgProbeMax, probes);
  // With strict eviction the history is the same key's cell in the previous
  // frame's table, which this cell links to and keeps alive.
  HgCell history = HG_AT(hgCells, slot);
  uint linked = 0u;
  if (pc.strict != 0u) {
    int previous = hgFind(pc.previousTable, index, key, pc.capacity, pc.probeWindow);
    if (previous >= 0) {
      history = HG_AT(hgCells, previous);
      linked = uint(previous) + 1u;
      HG_AT(hgCells, previous).lastSeen = pc.frameIndex;
    }
  }
  // The clamp's σ comes from the second moment of the samples as they
  // arrived, before clamping: a limit computed from clamped samples chases
  // itself down frame after frame (on Conference hpsf lost 15% of its
  // indirect light over 64 frames that way, and kept falling). The mean is
  // the cell's clamped one, which only makes σ larger: a more lenient clamp.
  // What the clamp takes off is not lost: it goes to the cell's tail, which
  // resolve averages over a much longer history (HG_TAIL_HISTORY), so the
  // light arrives, spread over many frames.
  vec3 sample_ = radiance;
  vec3 tail = vec3(0.0);
  float lum = giLuminance(sample_);
  if (pc.clampSigma > 0.0 && history.samples >= HG_CLAMP_MIN_SAMPLES) {
    // Never below twice the mean: where samples barely vary (σ ≈ 0), a cell
    // whose light is still building up over frames (nhpsf, anhpsf) must be
    // able to rise; fireflies are far above that.
    float mean = giLuminance(history.mean);
    float sigma = sqrt(max(history.lumMoment2 - mean * mean, 0.0));
    float limit = max(mean + pc.clampSigma * sigma, 2.0 * mean);
    if (lum > limit && lum > 0.0) {
      tail = sample_ * (1.0 - limit / lum);
      sample_ -= tail;
    }
  }
  bool overflowed = false;
  const uint before =
      hgAccumulate(slot, sample_ * pc.radianceScale, tail * pc.radianceScale, lum * pc.radianceScale, count, overflowed);
  if (overflowed) hgOverflowCount++;
  // A cell made by a deferred claim has no sentinel yet: the frame's first sample there traces it.
  const bool unwatched = pc.deferredClaims != 0u && before == 0u && history.sentinelSeen == 0u;
  needsSentinel = (created || unwatched) && pc.validationInterval > 0u;
  HG_AT(hgCells, slot).previousLod = hgPackPreviousLod(linked, lod);  // every writer of this key writes the same value
  hgInsertedCount++;
  return slot;
}

// A new cell's sentinel: the ray from the vertex that made it, with its
// direction as the cell stores it (packed), so the checks re-trace the very same ray.
HgSentinel hgNewCellSentinel(vec3 origin, vec3 direction, uint key) {
  return hgSentinelStart(origin, hgUnpackDirection(hgPackDirection(direction)), key);
}
// Stores the traced sentinel in the cell that made it.
void hgStoreSentinel(int slot, HgSentinel sentinel) {
  HG_AT(hgCells, slot).sentinelOrigin = sentinel.origin;
  HG_AT(hgCells, slot).sentinelDirection = hgPackDirection(sentinel.direction);
  HG_AT(hgCells, slot).sentinelSeen = hgPackSentinelSeen(sentinel.distance_, sentinel.light, pc.radianceScale);
}

// Last frame's radiance at (index, key) as the map passes it on (the cell's
// recent mean and tail); false when the cell is missing or holds too few samples.
bool hgReadCell(uint index, uint key, out vec3 mean) {
  mean = vec3(0.0);
  int slot = hgFind(hgReadTable(), index, key, pc.capacity, pc.probeWindow);
  if (slot < 0) return false;
  HgCell c = HG_AT(hgCells, slot);
  if (c.samples < pc.minSamples || c.frames == 0.0) return false;
  mean = hgCellRecent(c, pc.radianceScale) + c.tail;
  return true;
}


// A walk that starts at filter vertex s (it has a diffuse lobe): a cosine
// direction, feeding s's cell d; `travel` is what the next vertex's level of
// detail adds its segment to.
HgWalk hgWalkFrom(GiSurface s, HgDescriptor d, bool feeds, uint depth, float travel, inout GiRng rng) {
  HgWalk w;
  w.origin = giOffsetRay(s.position, s.geometricNormal);
  w.direction = hgPackDirection(giCosineSample(s.normal, giRandom2(rng)));
  w.index = hgIndexHash(d);
  w.key = feeds ? hgVerificationKey(d) : HG_EMPTY_KEY;
  w.throughput = vec3(1.0);
  w.travel = travel;
  w.state = hgWalkState(depth, false, d.lod);
  w.pad0 = 0u;
  return w;
}

// One segment of a walk as a part of a ray task (ray_loop.glsl): traces the
// walk's ray to w, adds what arrives (× throughput) to the cell it feeds,
// and moves the walk on. What arrives is NEE at w plus, when w is a filter
// vertex (it has a diffuse lobe), w's diffuse albedo × its cell from last
// frame's map. Then the walk goes on through one of w's lobes: the diffuse
// lobe starts a walk of w's own (feeding w's cell), the glossy lobe carries
// this walk on (what arrives next is more light for the same sample, through
// the glossy BSDF weight). A vertex with both picks the glossy lobe with its
// sampling probability and divides by it, so light through either lobe
// reaches the cell without bias; a pure metal always takes the glossy lobe.
// A miss ends the walk (after counting its zero sample). `arriving` is the
// radiance arriving at the walk's vertex (before throughput) once
// hgStepNext says GI_STEP_DONE.
#define HG_STEP_SEGMENT 0u   // the segment's ray is next
#define HG_STEP_WAITING 1u   // for its hit or NEE's light
#define HG_STEP_NEE 2u       // NEE at w is next
#define HG_STEP_INSERT 3u    // what arrived goes into the fed cell
#define HG_STEP_SENTINEL 4u     // the cell just made traces its sentinel
#define HG_STEP_CONTINUE 5u  // the walk moves on
#define HG_STEP_DONE 6u

struct HgStep {
  uint phase;        // HG_STEP_*
  vec3 direction;    // the segment's
  bool hit;          // it reached a vertex w
  GiSurface w;
  GiBsdf b;
  vec3 arriving;
  HgDescriptor dw;   // w's cell, where w is a filter vertex
  bool filterVertex;
  float segment;     // L∞ length of the segment
  int slot;          // the fed cell, while its sentinel is traced
  HgSentinel sentinel;
};

HgStep hgStepStart(HgWalk walk) {
  HgStep st;
  st.phase = HG_STEP_SEGMENT;
  st.direction = hgUnpackDirection(walk.direction);
  st.hit = false;
  st.arriving = vec3(0.0);
  st.filterVertex = false;
  st.segment = 0.0;
  st.slot = -1;
  return st;
}

// What arrived at the walk's vertex goes into the cell it feeds.
void hgStepInsert(inout HgStep st, HgWalk walk, inout GiRng rng) {
  st.phase = HG_STEP_CONTINUE;
  if (st.hit) {
    st.filterVertex = giHasDiffuseLobe(st.w.material);
    st.segment = hgLinf(walk.origin, st.w.position);
    if (st.filterVertex) {
      bool fromCamera = pc.secondaryLod == HG_LOD_CAMERA;
      st.dw = hgVertexDescriptor(st.w.position, st.w.normal, fromCamera ? giFrame.camera.position : walk.origin,
                                 fromCamera ? 0.0 : walk.travel, pc.secondaryWidthScale, rng);
      vec3 cell;
      hgReadCount++;
      if (hgReadCell(hgIndexHash(st.dw), hgVerificationKey(st.dw), cell)) st.arriving += st.b.diffuse * cell;
      else hgReadMissCount++;
    }
    if (!giKeepSample(st.arriving, vec3(0.0))) st.arriving = vec3(0.0);
  }
  if (walk.key == HG_EMPTY_KEY) return;
  vec3 added = walk.throughput * st.arriving;
  bool needsSentinel;
  st.slot = hgInsertSample(walk.index, walk.key, added, hgWalkContinues(walk) ? 0u : 1u, hgWalkLod(walk), needsSentinel);
  if (pc.mode == HG_MODE_ANHPSF && hgWalkDepth(walk) > 1u) hgTransported += giLuminance(added);
  if (needsSentinel) {
    st.sentinel = hgNewCellSentinel(walk.origin, st.direction, walk.key);
    st.phase = HG_STEP_SENTINEL;
  }
}

// The walk moves on through one of w's lobes, or ends.
void hgStepContinue(HgStep st, inout HgWalk walk, inout GiRng rng) {
  uint depth = hgWalkDepth(walk) + 1u;
  if (!st.hit) {
    walk.state = 0u;
    return;
  }
  float glossyChance = st.filterVertex ? st.b.specularProbability : 1.0;
  if (glossyChance > 0.0 && giRandom(rng) < glossyChance) {
    vec3 L, weight;
    if (!giSpecularSample(st.b, st.w.normal, -st.direction, giRandom2(rng), L, weight) ||
        dot(L, st.w.geometricNormal) <= 0.0) {
      walk.state = 0u;
    } else {
      walk.origin = giOffsetRay(st.w.position, st.w.geometricNormal);
      walk.direction = hgPackDirection(L);
      walk.throughput *= weight / glossyChance;
      walk.travel += st.segment;  // unfiltered travel, for every secondary-LOD rule that counts travel
      walk.state = hgWalkState(depth, true, hgWalkLod(walk));
    }
  } else {
    walk = hgWalkFrom(st.w, st.dw, true, depth, pc.secondaryLod == HG_LOD_PATH ? walk.travel + st.segment : 0.0, rng);
  }
}

uint hgStepNext(inout HgStep st, inout HgWalk walk, inout GiRng rng, out GiRay ray, out GiNeeRequest nee) {
  if (st.phase == HG_STEP_SEGMENT) {
    ray = giClosestRay(walk.origin, st.direction, 0.0, GI_FLT_MAX);
    st.phase = HG_STEP_WAITING;
    return GI_STEP_TRACE;
  }
  if (st.phase == HG_STEP_NEE) {
    nee = GiNeeRequest(st.w, st.b, -st.direction, false, rng, GI_NO_RESERVOIR);  // NEE alone: no emitter is hit after w
    st.phase = HG_STEP_WAITING;
    return GI_STEP_NEE;
  }
  if (st.phase == HG_STEP_INSERT) hgStepInsert(st, walk, rng);
  if (st.phase == HG_STEP_SENTINEL) {
    const uint step = hgSentinelNext(st.sentinel, ray, nee);
    if (step != GI_STEP_DONE) return step;
    hgStoreSentinel(st.slot, st.sentinel);
    st.phase = HG_STEP_CONTINUE;
  }
  if (st.phase == HG_STEP_CONTINUE) {
    hgStepContinue(st, walk, rng);
    st.phase = HG_STEP_DONE;
  }
  return GI_STEP_DONE;
}

void hgStepTakeHit(inout HgStep st, GiHit hit, GiSurface s) {
  if (st.phase == HG_STEP_SENTINEL) {
    hgSentinelTakeHit(st.sentinel, hit, s);
    return;
  }
  st.hit = hit.t >= 0.0;
  st.phase = HG_STEP_INSERT;
  if (!st.hit) return;
  st.w = s;
  st.b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
  st.phase = HG_STEP_NEE;
}

// NEE's light, and the random state after it: the walk's, unless the sentinel's (its own) asked.
void hgStepTakeNee(inout HgStep st, vec3 light, GiRng after, inout GiRng rng) {
  if (st.phase == HG_STEP_SENTINEL) {
    hgSentinelTakeNee(st.sentinel, light);
    return;
  }
  rng = after;
  st.arriving = light;
  st.phase = HG_STEP_INSERT;
}

// Adds this invocation's telemetry to the frame's, one atomic per subgroup and counter.
void hgFlushTelemetry() {
  uint sumInserted = subgroupAdd(hgInsertedCount), sumFailed = subgroupAdd(hgFailedCount);
  uint sumProbes = subgroupAdd(hgProbeCount), maxProbes = subgroupMax(hgProbeMax);
  uint sumOverflow = subgroupAdd(hgOverflowCount);
  float transported = subgroupAdd(hgTransported);
  uint sumReads = subgroupAdd(hgReadCount), sumMisses = subgroupAdd(hgReadMissCount);
  if (subgroupElect()) {
    if (sumInserted > 0u) atomicAdd(hgTelemetry.inserts, sumInserted);
    if (sumFailed > 0u) atomicAdd(hgTelemetry.failedInserts, sumFailed);
    if (sumProbes > 0u) atomicAdd(hgTelemetry.probeSum, sumProbes);
    if (maxProbes > 0u) atomicMax(hgTelemetry.probeMax, maxProbes);
    if (sumOverflow > 0u) atomicAdd(hgTelemetry.overflows, sumOverflow);
    if (sumReads > 0u) atomicAdd(hgTelemetry.reads, sumReads);
    if (sumMisses > 0u) atomicAdd(hgTelemetry.readMisses, sumMisses);
    if (transported > 0.0) atomicAdd(hgTelemetry.transported, hgToFixed(transported * pc.radianceScale));
  }
}

#endif
