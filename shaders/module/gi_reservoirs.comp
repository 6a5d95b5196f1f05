#version 460
// Reservoir resampling of the primary hits' point and spot lights and emissive
// triangles (ReSTIR DI, Bitterli et al. 2020), shared by every method
// (ReservoirSettings). A reservoir holds one light y, the samples M behind it
// and its weight W, an estimate of 1 / p(y) for the target p̂ = the luminance
// of the light's unshadowed reflected light f·Le·G: the pixel's direct light
// from the lights the reservoirs hold is then f·Le·G·V(y)·W, one shadow ray.
// y is a punctual light (p̂ and p counted per light), a point of an
// emissive triangle (per unit of area: lights.glsl's giPackEmissiveSample)
// or a direction to the sky (per steradian: giPackSkySample), as
// GiFrameConstants::primaryDirect says the frame's reservoirs hold them.
//   GI_RESERVOIR_TEMPORAL: `candidates` lights drawn from the scene's light
//     sampler (the tree's importance or power; with groupCandidates the emissive
//     triangles from the 8×8 group's shared draws, giDrawGroupCandidates) are resampled by p̂ / pdf;
//     last frame's temporal reservoir at the pixel's reprojection is merged
//     in (its M capped at maxHistory × candidates), where its guide says it
//     saw this surface; a reservoir far above its group's others is then dropped (giBoilingFilter). Last
//     frame's set → this frame's (A and B alternate: GiReservoirPush::readSet). Without the merge
//     the frame's one set, half the bytes (GiReservoirPush::frameSet, giLoadReservoir).
//   GI_RESERVOIR_SPATIAL: the pixel's temporal reservoir and `neighbours`
//     others from a disc of `radius` pixels, those whose surface agrees in
//     depth and normal, are merged by p̂ at this pixel (giSpatialReservoir
//     says with which weights), and the survivor's shadow ray traced: the
//     pick, its light and W where the pixel sees it, which the tracing passes
//     add without a ray of their own (giPrimaryReservoir). The spatial result
//     is not fed back: the next frame reuses the pixel's temporal reservoir,
//     not a mix of its neighbours' (measured: fed back, in a room of a
//     thousand lamps whose best lights change from pixel to pixel, the
//     neighbours' samples diluted each pixel's own history).
//   GI_RESERVOIR_PICK: without neighbours, the temporal pass and the survivor's shadow ray in one dispatch:
//     the spatial pass would merge the pixel's reservoir alone and keep its W (one pass's G-buffer reads and
//     target fewer). Not with the sky in the reservoirs, whose failed directions (giStoreFailedSky) go to the
//     set this pass reads at other pixels' reprojections.
// With ReservoirSettings::sky they hold the sky's map too (GI_PRIMARY_DIRECT_SKY): a share of the candidates
// are directions drawn from it, their target the sky's light weighed against BSDF sampling (lights.glsl's
// giReservoirSkyPdf), and a BSDF-sampled ray that leaves the scene from the primary hit takes the rest; the
// sky's share and target are scaled by its measured visibility (giCountSkyPicks), and a sky direction whose
// shadow ray failed at a pixel is not merged into its reservoir again (giStoreFailedSky).
// Directional lights and a constant sky are NEE's (and BSDF sampling's) at every vertex as before: p̂ = 0.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "gi_frame.glsl"
#include "lights.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiReservoirPush pc; };

struct GiReservoir {
  uint light;       // GI_RESERVOIR_EMPTY: none
  float weightSum;  // Σ of the merged weights
  float M;          // samples behind the light
  float target;     // p̂(light) at this pixel
};

GiReservoir giEmptyReservoir() { return GiReservoir(GI_RESERVOIR_EMPTY, 0.0, 0.0, 0.0); }

// p̂: the luminance of the light's unshadowed reflected light at s (0 for directional lights, none, and
// lights the frame's reservoirs do not hold), and for a triangle's point the triangle's area
// (giPrepareReservoirLight; skyShare: giReservoirSkyShare at s). A sky direction's is scaled by the sky's
// measured visibility (giReservoirsSkyVisibility), one factor over the frame: any positive target keeps the
// estimate f·V·W unbiased, and this one stops an occluded sky from winning reservoirs by its unshadowed light
// whose shadow rays then fail.
float giReservoirTarget(uint light, GiSurface s, GiBsdf b, vec3 V, float skyShare, out float area) {
  area = 0.0;
  if (light == GI_RESERVOIR_EMPTY) return 0.0;
  GiShadowRay ray;
  if (!giPrepareReservoirLight(light, s, b, V, skyShare, ray, area)) return 0.0;
  return giLuminance(ray.contribution) * (giIsSkySample(light) ? giReservoirsSkyVisibility() : 1.0);
}
float giReservoirTarget(uint light, GiSurface s, GiBsdf b, vec3 V, float skyShare) {
  float area;
  return giReservoirTarget(light, s, b, V, skyShare, area);
}
// At a neighbour's surface, one light there: its sky share only where the light is the sky.
float giReservoirTarget(uint light, GiSurface s, GiBsdf b, vec3 V) {
  return giReservoirTarget(light, s, b, V, giReservoirSkyShareOf(light, s));
}

// Streams in a sample of weight w (p̂/pdf for a candidate, p̂·W·M for a reservoir) standing for M samples.
void giReservoirMerge(inout GiReservoir r, uint light, float target, float weight, float M, float u) {
  r.M += M;
  if (!(weight > 0.0)) return;
  r.weightSum += weight;
  if (u * r.weightSum < weight) {
    r.light = light;
    r.target = target;
  }
}

// The 8×8 group's shared candidates for the emissive triangles (pc.groupCandidates, where they are walked down
// their tree): each invocation draws pc.groupCandidates of them, down the tree at the group's surface (the
// covered pixel nearest the group's centre) or, with pc.groupPowerShare, by power, so that a triangle a pixel
// sees and the group's surface does not keeps a density above 0. A draw's chance is the mixture's,
// powerShare·power + (1 − powerShare)·tree, the same for every pixel of the group: each pixel's RIS over the
// draws it takes stays unbiased (a candidate's weight needs only its own density; draws shared between pixels
// correlate them, as RTXDI's presampled light tiles do). A pixel's `candidates` walks fall to the
// pc.groupCandidates its invocation makes. The draws are stratified over [0, 1) like a pixel's own picks, and a
// pixel takes every stride-th (a stride coprime to their count, so that the starts give as many different
// sets as there are draws) from a random start (giGroupStride): its candidates spread over the tree too.
#define GI_GROUP_PIXELS (GI_GROUP_SIZE * GI_GROUP_SIZE)
#define GI_GROUP_DRAWS_MAX (8u * GI_GROUP_PIXELS)      // ReservoirSettings::groupCandidates ≤ 8
shared uint giGroupDraws[GI_GROUP_DRAWS_MAX];         // an emissive triangle's entry, or GI_RESERVOIR_EMPTY
shared float giGroupDrawChances[GI_GROUP_DRAWS_MAX];  // the chance of its pick under the mixture
shared uint giGroupSurfaceRank;                       // the lending pixel: its squared distance to the centre, index
shared vec3 giGroupPosition, giGroupNormal;           // its surface (world; geometric normal)

// Whether this pass draws candidates and merges last frame's reservoir: the temporal pass, alone or with the
// survivor's shadow ray (GI_RESERVOIR_PICK).
bool giDrawsCandidates() { return pc.mode != GI_RESERVOIR_SPATIAL; }

// Whether the temporal pass takes its emissive candidates from the group's draws (uniform over the dispatch).
bool giSharesGroupDraws() {
  return giDrawsCandidates() && pc.groupCandidates != 0u && giReservoirsHoldEmissive() &&
         giEmissiveTree();
}
uint giGroupDrawCount() { return min(pc.groupCandidates, 8u) * GI_GROUP_PIXELS; }

// Every invocation of the group calls it (barriers); covered: its pixel has a surface at x (geometric normal ng).
void giDrawGroupCandidates(bool covered, vec3 x, vec3 ng, inout GiRng rng) {
  const uint index = gl_LocalInvocationIndex;
  if (index == 0u) giGroupSurfaceRank = 0xffffffffu;
  barrier();
  const ivec2 fromCentre = 2 * ivec2(gl_LocalInvocationID.xy) - ivec2(GI_GROUP_SIZE - 1u);  // in half pixels
  const uint rank = (uint(dot(fromCentre, fromCentre)) << 8u) | index;
  if (covered) atomicMin(giGroupSurfaceRank, rank);
  barrier();
  if (covered && giGroupSurfaceRank == rank) {
    giGroupPosition = x;
    giGroupNormal = ng;
  }
  barrier();
  const uint draws = giGroupDrawCount();
  const bool lit = giGroupSurfaceRank != 0xffffffffu;  // else no pixel of the group takes a candidate
  GiRng group = giRngCreate(gl_WorkGroupID.xy, giFrame.frameIndex, pc.seed, GI_STREAM_RESERVOIR_GROUPS);
  const float offset = giRandom(group);
  const float powerShare = pc.groupPowerShare;
  for (uint slot = index; slot < draws; slot += GI_GROUP_PIXELS) {
    uint k = GI_RESERVOIR_EMPTY;
    float chance = 0.0;
    if (lit) {
      const float u = fract(offset + float(slot) / float(draws));
      float tree = 0.0;
      if (giRandom(rng) < powerShare) {
        k = giPickEmissiveTriangle(u);
        tree = giTreeLeafChance(true, sceneEmissiveLeaf(k), giGroupPosition, giGroupNormal);
      } else {
        k = giPickFromTree(true, 0u, giGroupPosition, giGroupNormal, u, tree);
        if (!(tree > 0.0)) k = GI_RESERVOIR_EMPTY;  // no triangle can light the group's surface: this draw is none
      }
      if (k != GI_RESERVOIR_EMPTY) chance = powerShare * giEmissiveTriangleChance(k) + (1.0 - powerShare) * tree;
    }
    giGroupDraws[slot] = k;
    giGroupDrawChances[slot] = chance;
  }
  barrier();
}

uint giGcd(uint a, uint b) {
  while (b != 0u) {
    const uint r = a % b;
    a = b;
    b = r;
  }
  return a;
}
// The step between the group draws a pixel's candidates take (giTemporalReservoir: from a random start):
// the first at or above draws / candidates that is coprime to the draws' count.
uint giGroupStride(uint draws) {
  uint stride = max(1u, draws / max(pc.candidates, 1u));
  while (giGcd(stride, draws) != 1u) stride++;
  return stride;
}

// A candidate from the scene's samplers and the chance of its pick (0: none can light x): a punctual
// light, an emissive triangle's sample point (whose density is that chance over the triangle's area,
// which its target brings: giReservoirTarget), or a direction from the sky's map (a density per steradian:
// giReservoirSkyPdf). The sky takes giReservoirSkyShare of the candidates; where the reservoirs hold both
// kinds of lights, each is drawn half of the rest. `u` picks the light (the caller stratifies it over the
// candidates; skyShare is giReservoirSkyShare at s); with giSharesGroupDraws an emissive triangle is the
// group's draw in `slot` instead.
uint giReservoirCandidate(GiSurface s, float u, uint slot, float skyShare, inout GiRng rng, out float chance) {
  if (skyShare >= 1.0 || (skyShare > 0.0 && giRandom(rng) < skyShare)) {
    float pdf;
    const uint direction = giPackSkySample(giSampleSkyMap(giRandom2(rng), pdf));
    chance = skyShare * giSkyLightPdf(giSkySampleDirection(direction));  // the density where the packed one points
    return direction;
  }
  const float emissiveShare = giReservoirsHoldEmissive() ? (giReservoirsHoldPunctual() ? 0.5 : 1.0) : 0.0;
  if (emissiveShare >= 1.0 || (emissiveShare > 0.0 && giRandom(rng) < emissiveShare)) {
    if (giSharesGroupDraws()) {
      const uint k = giGroupDraws[slot];
      chance = (1.0 - skyShare) * emissiveShare * giGroupDrawChances[slot];
      return k == GI_RESERVOIR_EMPTY ? GI_RESERVOIR_EMPTY : giPackEmissiveSample(k, giRandom2(rng));
    }
    const bool tree = giEmissiveTree();
    float pick = 1.0;
    const uint k = tree ? giPickFromTree(true, 0u, s.position, s.geometricNormal, u, pick) : giPickEmissiveTriangle(u);
    if (!tree) pick = giEmissiveTriangleChance(k);
    chance = (1.0 - skyShare) * emissiveShare * pick;
    return giPackEmissiveSample(k, giRandom2(rng));
  }
  uint light;
  if (giLightSampler() == LIGHT_SAMPLER_TREE)
    light = giPickFromTree(false, 0u, s.position, s.geometricNormal, u, chance);
  else light = giPickPunctual(u, chance);
  chance *= (1.0 - skyShare) * (1.0 - emissiveShare);
  return light;
}

// A target evaluated at a neighbour's surface, cut to a float's upper 12 bits (3 bits of mantissa: 12% at
// most): the temporal pass stores each reservoir's own target p̂_i(y_i) so cut, and the spatial pass
// evaluates every other light at a neighbour's surface through the same cut, so the MIS weights of one y
// still sum to one exactly (the cut changes the weights, which any consistent choice keeps unbiased, not the
// light), and pairwise MIS evaluates no neighbour's own light again.
#define GI_TARGET_SHIFT 20u  // the target keeps a float's upper 32 − 20 = 12 bits
#define GI_TARGET_BITS (0xffffffffu << GI_TARGET_SHIFT)
float giNeighbourTarget(float target) { return uintBitsToFloat(floatBitsToUint(target) & GI_TARGET_BITS); }

// z: M as a half float (at most 1000 × 64 = 64,000 by the settings' ranges: under the half's 65,504) in
// the low 16 bits, giNeighbourTarget of p̂ at the reservoir's own pixel in the high 12 (bits 16–19 zero).
uint giPackConfidence(float M, float target) {
  return floatBitsToUint(giNeighbourTarget(target)) | (packHalf2x16(vec2(M, 0.0)) & 0xffffu);
}
uvec4 giStoredReservoir(GiReservoir r, float W, uint guide) {
  return uvec4(r.light, floatBitsToUint(W), giPackConfidence(r.M, r.target), guide);
}

float giStoredW(uvec4 v) { return uintBitsToFloat(v.y); }
float giStoredM(uvec4 v) { return unpackHalf2x16(v.z & 0xffffu).x; }
// p̂ of the reservoir's light at its own pixel, as giNeighbourTarget cut it.
float giStoredTarget(uvec4 v) { return uintBitsToFloat(v.z & GI_TARGET_BITS); }

// The temporal reservoirs, this frame's and last frame's, as giStoredReservoir wrote them. With
// pc.frameSet (no merge) only this frame's, as its light (x) and in y, W's bits rounded to its upper 20
// (11 bits of mantissa: 0.025% at most) with the stored target's 12 in their place (giStoreReservoir): its
// M is the candidates' count, or 0 where the boiling filter dropped it (W's sign bit), and its guide is
// packed from the G-buffer as the temporal pass packed it, the same bits.
#define GI_RESERVOIR_DROPPED 0x80000000u
#define GI_FRAME_SET_TARGET_BITS ((1u << (32u - GI_TARGET_SHIFT)) - 1u)  // y's low 12: the target's
#define GI_FRAME_SET_W_BITS (~(GI_RESERVOIR_DROPPED | GI_FRAME_SET_TARGET_BITS))
uvec4 giLoadReservoir(ivec2 p, bool current) {
  if (pc.frameSet == 0u)
    return (pc.readSet == 0u) == current ? imageLoad(giReservoirsB, p) : imageLoad(giReservoirsA, p);
  if (!giGbCovered(p)) return uvec4(GI_RESERVOIR_EMPTY, 0u, 0u, 0u);
  const uvec2 v = imageLoad(giFrameReservoirs, p).xy;
  const float M = (v.y & GI_RESERVOIR_DROPPED) != 0u ? 0.0 : float(pc.candidates);
  return uvec4(v.x, v.y & GI_FRAME_SET_W_BITS, giPackConfidence(M, uintBitsToFloat(v.y << GI_TARGET_SHIFT)),
               giPackGuide(giGbNormal(p), giGbViewDepth(p) / giFrame.depthScale));
}

// The temporal pass's reservoir at p: this frame's set (A or B), or with pc.frameSet the frame's.
void giStoreReservoir(ivec2 p, uvec4 stored) {
  if (pc.frameSet != 0u) {
    const uint dropped = giStoredM(stored) == 0.0 ? GI_RESERVOIR_DROPPED : 0u;
    const uint toNearest = (GI_FRAME_SET_TARGET_BITS + 1u) / 2u;  // W rounded to its upper 20 bits (W ≥ 0)
    const uint W = min(stored.y + toNearest, 0x7f800000u) & GI_FRAME_SET_W_BITS;
    imageStore(giFrameReservoirs, p, uvec4(stored.x, dropped | W | (stored.z >> GI_TARGET_SHIFT), 0u, 0u));
  }
  else if (pc.readSet == 0u) imageStore(giReservoirsB, p, stored);
  else imageStore(giReservoirsA, p, stored);
}

// Visibility reuse for the sky (RTXDI's, for sky directions only): with the merged sets the spatial pass
// leaves at p the sky direction whose shadow ray failed there (GI_RESERVOIR_EMPTY: none) in the set this
// frame's temporal pass read, which no pass reads again until the next frame's temporal pass at p takes it
// before it overwrites it: a last-frame reservoir holding that direction is then merged with weight 0 and
// its M (the ReSTIR paper's visibility reuse: the history counts its samples as dark ones). Unshadowed
// targets otherwise keep a hidden sun in a pixel's reservoir for as many frames as its M holds, every one of
// them dark. Biased, measured (docs/RESULTS.md, "The sky in the reservoirs": about -1% of the mean; merged
// with neither weight nor M, +8%).
void giStoreFailedSky(ivec2 p, uint light) {
  if (pc.readSet == 0u) imageStore(giReservoirsA, p, uvec4(light, 0u, 0u, 0u));
  else imageStore(giReservoirsB, p, uvec4(light, 0u, 0u, 0u));
}
uint giFailedSky(ivec2 p) { return (pc.readSet == 0u ? imageLoad(giReservoirsB, p) : imageLoad(giReservoirsA, p)).x; }
bool giReusesSkyVisibility() { return pc.frameSet == 0u && giReservoirsSampleSky(); }

// GI_RESERVOIR_TEMPORAL at a covered pixel: candidates and last frame's reservoir, and the kept light's
// estimate of the pixel's unshadowed light, p̂·W (luminance), for the boiling filter.
uvec4 giTemporalReservoir(ivec2 p, GiSurface s, GiBsdf b, vec3 V, vec3 n, float depth, uint guide, inout GiRng rng,
                          out float estimate) {
  GiReservoir r = giEmptyReservoir();
  const float skyShare = giReservoirSkyShare(s.position, s.geometricNormal);
  // The candidates' picks are stratified: one random offset, then equal steps, so each u is uniform (each
  // candidate keeps the sampler's density, as RIS asks) and together they cover [0, 1) evenly, which spreads
  // them over the tree's leaves instead of letting them crowd.
  const float offset = giRandom(rng);
  const uint draws = giSharesGroupDraws() ? giGroupDrawCount() : 0u;
  const uint start = draws > 0u ? min(uint(giRandom(rng) * float(draws)), draws - 1u) : 0u;
  const uint stride = draws > 0u ? giGroupStride(draws) : 0u;
  for (uint i = 0u; i < pc.candidates; ++i) {
    float chance, area = 0.0;
    const float u = fract(offset + float(i) / float(pc.candidates));
    const uint light = giReservoirCandidate(s, u, draws > 0u ? (start + i * stride) % draws : 0u, skyShare, rng, chance);
    const float target = chance > 0.0 ? giReservoirTarget(light, s, b, V, skyShare, area) : 0.0;
    const float density = area > 0.0 ? chance / area : chance;  // a triangle's point: per unit of its area
    giReservoirMerge(r, light, target, target / max(density, 1e-30), 1.0, giRandom(rng));
  }
  const ivec2 q = ivec2(floor(giPreviousPosition(p)));
  if (pc.temporal != 0u && giInPreviousFrame(q)) {
    const uvec4 previous = giLoadReservoir(q, false);
    const uint failed = giReusesSkyVisibility() ? giFailedSky(p) : GI_RESERVOIR_EMPTY;
    if (previous.x != GI_RESERVOIR_EMPTY &&
        giHistoryTexelAgrees(giUnpackGuide(previous.w), n, giPreviousViewDepth(s.position), depth, pc.depthTolerance,
                             pc.cosNormalLimit)) {
      const float M = min(giStoredM(previous), pc.maxHistory * float(pc.candidates));
      const float target = previous.x == failed ? 0.0 : giReservoirTarget(previous.x, s, b, V, skyShare);
      giReservoirMerge(r, previous.x, target, target * giStoredW(previous) * M, M, giRandom(rng));
    }
  }
  const float W = r.target > 0.0 ? r.weightSum / (r.M * r.target) : 0.0;
  estimate = r.target * W;
  return giStoredReservoir(r, W, guide);
}

// RTXDI's boiling filter over the 8×8 group: a temporal reservoir whose estimate is above
// pc.boilingFilter times the mean of the group's other non-zero estimates is dropped (its guide kept). A
// light drawn with a density far below its share of the target has a weight the temporal merge keeps for
// frames and the spatial pass hands to the neighbours: a blotch that outlives its one frame. The group's
// sums are its subgroups' (one shared word each), so each invocation reads gl_NumSubgroups of them. Every
// invocation of the group calls it (a barrier).
shared float giSubgroupEstimates[GI_GROUP_SIZE * GI_GROUP_SIZE];
shared uint giSubgroupCounts[GI_GROUP_SIZE * GI_GROUP_SIZE];
uvec4 giBoilingFilter(uvec4 stored, float estimate) {
  const float subgroupSum = subgroupAdd(estimate);  // estimates are ≥ 0: the zeros add nothing
  const uint subgroupCount = subgroupAdd(estimate > 0.0 ? 1u : 0u);
  if (subgroupElect()) {
    giSubgroupEstimates[gl_SubgroupID] = subgroupSum;
    giSubgroupCounts[gl_SubgroupID] = subgroupCount;
  }
  barrier();
  float sum = 0.0;
  uint count = 0u;
  for (uint i = 0u; i < gl_NumSubgroups; ++i) {
    sum += giSubgroupEstimates[i];
    count += giSubgroupCounts[i];
  }
  if (estimate > 0.0) {
    sum -= estimate;
    count--;
  }
  return count > 0u && estimate > pc.boilingFilter * sum / float(count) ? uvec4(GI_RESERVOIR_EMPTY, 0u, 0u, stored.w)
                                                                        : stored;
}

// GI_RESERVOIR_SPATIAL at a covered pixel: its reservoir and its neighbours' merged, then the survivor's
// shadow ray. Reservoir i (0 = the pixel's own) came from surface i, whose target p̂_i differs from this
// pixel's p̂: with `unbiased` each is weighed by the balance heuristic over the surfaces,
// m_i(y) = M_i·p̂_i(y) / Σ_j M_j·p̂_j(y) (generalised RIS, Lin et al. 2022; the ReSTIR paper's MIS form),
// so a light that is bright here and dim where it was drawn cannot become a firefly ((N+1)² target
// evaluations for N neighbours), or with `pairwise` by pairwise MIS (giPairwiseShares, 2N+1); else by
// M_i / Σ M_j (the paper's biased 1/M).
#define GI_SPATIAL_MAX 9u

// Pairwise MIS (Lin et al. 2022, §7.1; Bitterli's thesis): the pixel's own reservoir c is the canonical
// technique, and each of the N neighbours i is weighed against it alone, with c's confidence split over the
// N pairs: m_i(y) = M_i·p̂_i(y) / (M_i·p̂_i(y) + M_c/N·p̂_c(y)) / N, and c's weight the mean of its N pair
// weights, so the weights of every y sum to one as the balance heuristic's do, and equal them where the
// surfaces agree. Per neighbour the target of its light here and of the pixel's light at the neighbour,
// p̂_i(y_c); its own light's p̂_i(y_i) is the one the temporal pass stored (giStoredTarget), where the
// balance heuristic makes one a neighbour for every merged light.
void giPairwiseShares(uvec4 found[GI_SPATIAL_MAX], ivec2 at[GI_SPATIAL_MAX], uint count,
                      float here[GI_SPATIAL_MAX], GiSurface s, GiBsdf b, vec3 V, inout float share[GI_SPATIAL_MAX]) {
  if (count < 2u) {
    share[0] = 1.0;
    return;
  }
  const float N = float(count - 1u);
  const float canonicalM = giStoredM(found[0]) / N;
  float canonical = 0.0;
  for (uint i = 1u; i < count; ++i) {
    vec3 Vi;
    const GiSurface si = giGbSurface(at[i], Vi);
    const GiBsdf bi = giMakeBsdf(si.material.baseColor, si.material.metallic, si.material.roughness, si.material.flags);
    const float Mi = giStoredM(found[i]);
    const float drawn = here[i] > 0.0 ? Mi * giStoredTarget(found[i]) : 0.0;
    const float mine = canonicalM * here[i];
    share[i] = drawn > 0.0 ? drawn / ((drawn + mine) * N) : 0.0;
    const float theirs = here[0] > 0.0 ? Mi * giNeighbourTarget(giReservoirTarget(found[0].x, si, bi, Vi)) : 0.0;
    const float canonicalHere = canonicalM * here[0];
    canonical += canonicalHere > 0.0 ? canonicalHere / (canonicalHere + theirs) : 0.0;
  }
  share[0] = canonical / N;
}
uint giSkyPickTested = 0u, giSkyPickVisible = 0u;  // this pixel's pick is a sky direction; its ray saw the sky

// The pick the tracing passes take (giPrimaryReservoir): the survivor's light and its W, 0 where its shadow ray
// is blocked (an occluded light brings nothing this frame; the reservoirs that are reused keep estimating the
// unshadowed light, whose visibility the pixel that picks it tests). A sky direction's outcome is counted
// (giCountSkyPicks). skyShare: giReservoirSkyShare at s.
uvec4 giVisiblePick(uint light, float W, GiSurface s, GiBsdf b, vec3 V, float skyShare) {
  GiShadowRay shadow;
  float area;
  if (W > 0.0 && giPrepareReservoirLight(light, s, b, V, skyShare, shadow, area)) {
    const bool visible = giTraceVisible(shadow.origin, shadow.direction, 0.0, shadow.tMax);
    if (giIsSkySample(light)) {
      giSkyPickTested = 1u;
      giSkyPickVisible = visible ? 1u : 0u;
    }
    if (!visible) W = 0.0;
  }
  return uvec4(light, floatBitsToUint(W), 0u, 0u);
}
uvec4 giSpatialReservoir(ivec2 p, GiSurface s, GiBsdf b, vec3 V, vec3 n, float depth, inout GiRng rng) {
  uvec4 found[GI_SPATIAL_MAX];
  ivec2 at[GI_SPATIAL_MAX];
  found[0] = giLoadReservoir(p, true);
  at[0] = p;
  uint count = 1u;
  for (uint i = 0u; i < min(pc.neighbours, GI_SPATIAL_MAX - 1u); ++i) {
    const vec2 u = giRandom2(rng);
    const float angle = 6.28318530718 * u.y;
    const ivec2 q = p + ivec2(round(pc.radius * sqrt(u.x) * vec2(cos(angle), sin(angle))));
    if (q == p || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(giFrame.size)))) continue;
    const uvec4 other = giLoadReservoir(q, true);
    const vec4 g = giUnpackGuide(other.w);
    if (!giDepthAgrees(g.w * giFrame.depthScale, depth, pc.depthTolerance) || dot(g.xyz, n) < pc.cosNormalLimit) continue;
    found[count] = other;
    at[count] = q;
    count++;
  }
  // Each light's target here, and its share: M_i, or with `unbiased` the balance heuristic, whose sums read
  // each surface once.
  float here[GI_SPATIAL_MAX], share[GI_SPATIAL_MAX], sum[GI_SPATIAL_MAX];
  const float skyShare = giReservoirSkyShare(s.position, s.geometricNormal);
  for (uint i = 0u; i < count; ++i) {
    here[i] = giReservoirTarget(found[i].x, s, b, V, skyShare);
    share[i] = giStoredM(found[i]);
    sum[i] = 0.0;
  }
  if (pc.unbiased != 0u && pc.pairwise != 0u) {
    giPairwiseShares(found, at, count, here, s, b, V, share);
  } else if (pc.unbiased != 0u) {
    for (uint j = 0u; j < count; ++j) {
      vec3 Vj = V;
      GiSurface sj = s;
      if (j > 0u) sj = giGbSurface(at[j], Vj);
      const GiBsdf bj = giMakeBsdf(sj.material.baseColor, sj.material.metallic, sj.material.roughness, sj.material.flags);
      const float Mj = giStoredM(found[j]);
      for (uint i = 0u; i < count; ++i) {
        const float pj = j == 0u || !(here[i] > 0.0) ? here[i]
                         : i == j                   ? giStoredTarget(found[i])
                                                    : giNeighbourTarget(giReservoirTarget(found[i].x, sj, bj, Vj));
        sum[i] += Mj * pj;
        if (i == j) share[i] = Mj * pj;
      }
    }
    for (uint i = 0u; i < count; ++i) share[i] = sum[i] > 0.0 ? share[i] / sum[i] : 0.0;
  }
  GiReservoir r = giEmptyReservoir();
  for (uint i = 0u; i < count; ++i)
    giReservoirMerge(r, found[i].x, here[i], here[i] * giStoredW(found[i]) * share[i], giStoredM(found[i]), giRandom(rng));
  const float W = r.target > 0.0 ? r.weightSum / (r.target * (pc.unbiased != 0u ? 1.0 : r.M)) : 0.0;
  return giVisiblePick(r.light, W, s, b, V, skyShare);
}

// The frame's sky picks and those that saw the sky, into GiCounters (one atomic pair per subgroup): the host
// turns recent frames' ratio into GiFrameConstants::skyVisibility (frame.cpp's updateSkyVisibility).
void giCountSkyPicks() {
  const uint tested = subgroupAdd(giSkyPickTested), visible = subgroupAdd(giSkyPickVisible);
  if (subgroupElect() && tested > 0u) {
    atomicAdd(giCounters.skyPicksTested, tested);
    atomicAdd(giCounters.skyPicksVisible, visible);
  }
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  const bool inside = giInFrame(gl_GlobalInvocationID.xy);
  uvec4 stored = uvec4(GI_RESERVOIR_EMPTY, 0u, 0u, 0u);
  float estimate = 0.0;
  const bool covered = inside && giGbCovered(p);
  // Two streams a frame: the candidates' (the pick pass's too) and the spatial pass's.
  const uint stream = giDrawsCandidates() ? 0u : 1u;
  GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex * 2u + stream, pc.seed, GI_STREAM_RESERVOIRS);
  vec3 V = vec3(0.0);
  GiSurface s;
  GiBsdf b;
  if (covered) {
    s = giGbSurface(p, V);
    b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
  }
  if (giSharesGroupDraws())
    giDrawGroupCandidates(covered, covered ? s.position : vec3(0.0), covered ? s.geometricNormal : vec3(0.0), rng);
  if (covered) {
    const vec3 n = giGbNormal(p);
    const float depth = giGbViewDepth(p);
    const uint guide = giPackGuide(n, depth / giFrame.depthScale);
    stored = giDrawsCandidates() ? giTemporalReservoir(p, s, b, V, n, depth, guide, rng, estimate)
                                 : giSpatialReservoir(p, s, b, V, n, depth, rng);
  }
  if (giDrawsCandidates() && pc.boilingFilter > 0.0) stored = giBoilingFilter(stored, estimate);
  if (inside) {
    // The pick pass keeps its reservoir for the next frame's merge only (without it nothing reads the frame's set).
    if (pc.mode == GI_RESERVOIR_TEMPORAL || (pc.mode == GI_RESERVOIR_PICK && pc.frameSet == 0u))
      giStoreReservoir(p, stored);
    // W is 0 where the pixel has no surface or its reservoir no light (nor after the boiling filter dropped it).
    if (pc.mode == GI_RESERVOIR_PICK)
      stored = giVisiblePick(stored.x, giStoredW(stored), s, b, V, giReservoirSkyShare(s.position, s.geometricNormal));
    if (pc.mode != GI_RESERVOIR_TEMPORAL) imageStore(giReservoirPick, p, stored);
    if (pc.mode == GI_RESERVOIR_SPATIAL && giReusesSkyVisibility())
      giStoreFailedSky(p, giSkyPickTested != 0u && giSkyPickVisible == 0u ? stored.x : GI_RESERVOIR_EMPTY);
  }
  if (pc.mode != GI_RESERVOIR_TEMPORAL && giReservoirsSampleSky()) giCountSkyPicks();
  giCountRays(inside);
}
