#version 460
// Temporal reprojection of a screen-space method's noisy light (SVGF's
// temporal accumulation, Schied et al. 2017 §4.1): last frame's accumulated
// direct and demodulated indirect light are fetched where the motion vector
// says this pixel was, bilinearly; a tap counts only if the surface it saw
// had this pixel's normal and the depth this pixel's point had from the
// previous camera (static geometry) or has now (moving geometry). The pixel
// then takes 1/(frames + 1) of this frame, at least minBlend; disoccluded
// pixels start over. The results replace the noisy direct and indirect, so
// the method's filter works on them. Emission is not accumulated: it is
// exact in every frame; the direct light is accumulated over the base colour,
// and only where the scene has area lights (emissive triangles or a sky) or
// NEE picks one of several punctual lights (gi::picksPunctualLights):
// every punctual light's exact direct light has no noise to average, only detail to blur.
// With temporal gradients (temporal.glsl) the new frame weighs more where the
// light changed: (1 − λ)·weight + λ, and the history count drops to match.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiTemporalPush pc; };

struct History {
  vec3 direct, indirect;
  vec2 mean, square;  // svgf: luminance mean and mean square of direct (x) and indirect (y)
  float frames;  // 0: none
};

// Last frame's texel q: its guide (unit normal, view depth / depthScale) and its direct light over the
// base colour with its frames (a). With directOnly (the hash methods) both come from the one packed
// texel; otherwise from the set last frame wrote.
struct HistoryTexel {
  vec4 guide, direct;
};
HistoryTexel readTexel(ivec2 q) {
  if (pc.directOnly != 0u) {
    const GiPackedHistory h = giUnpackHistory(imageLoad(giHistoryPacked, q).xy);
    return HistoryTexel(h.guide, vec4(h.direct / pc.historyScale, h.frames));
  }
  vec4 direct = pc.readSet == 0u ? giLoadHistoryDirectA(q) : giLoadHistoryDirectB(q);
  if (pc.moments != 0u) direct.a = giLoadSvgfFrames(pc.readSet, q);  // svgf's alpha holds its direct mean
  return HistoryTexel(giPreviousGuide(q), direct);
}
vec4 readIndirect(ivec2 q) { return giLoadHistoryIndirect(pc.readSet, q); }
// The guide keeps view depth over the scene extent: half floats then hold it
// at any scene scale (metres would overflow past 65504).
// The history frames ride in the direct image's alpha; svgf's alphas hold its luminance means instead,
// and its moments image the variances and the frames (gi_frame.glsl's giLoadMoments). With directOnly
// the packed history is written by the composite pass, once every neighbour has read it: this pass
// hands the frames on in the direct output's alpha.
// The indirect history's alpha carries the noisy image's (sspsf's filter-vertex flag), for the screen
// filters that read it (MethodPlan::filtersReadHistory).
// This frame's guide is stored later (GiCompositePush::writesGuide, svgf's variance pass): neighbours
// read last frame's here.
void write(ivec2 p, vec3 direct, vec3 indirect, float frames, GiMoments moments, float noisyAlpha) {
  if (pc.directOnly != 0u) return;
  const vec2 alphas = pc.moments != 0u ? giSvgfMeanAlphas(moments) : vec2(frames, noisyAlpha);
  if (pc.moments != 0u) giStoreSvgfState(1u - pc.readSet, p, moments, frames);
  if (pc.readSet == 0u) {
    giStoreHistoryDirectB(p, direct, alphas.x);
    giStoreHistoryIndirectB(p, indirect, alphas.y);
  } else {
    giStoreHistoryDirectA(p, direct, alphas.x);
    giStoreHistoryIndirectA(p, indirect, alphas.y);
  }
}

History reproject(ivec2 p, vec3 n, float depth, vec3 world) {
  History h = History(vec3(0.0), vec3(0.0), vec2(0.0), vec2(0.0), 0.0);
  if (pc.reset != 0u) return h;
  // Continuous pixel coordinates in the previous frame, then its four nearest texel centres.
  const vec2 previous = giPreviousPosition(p) - 0.5;
  const ivec2 base = ivec2(floor(previous));
  const vec2 f = previous - vec2(base);
  const float staticDepth = giPreviousViewDepth(world);
  float weights = 0.0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const ivec2 q = base + ivec2(i, j);
      if (!giInPreviousFrame(q)) continue;
      const HistoryTexel texel = readTexel(q);
      if (!giHistoryTexelAgrees(texel.guide, n, staticDepth, depth, pc.depthTolerance, pc.cosNormalLimit)) continue;
      const float w = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y);
      if (w <= 0.0) continue;
      const vec4 direct = texel.direct;
      h.direct += w * direct.rgb;
      if (pc.directOnly == 0u) h.indirect += w * readIndirect(q).rgb;
      if (pc.moments != 0u) {
        const GiMoments m = giLoadMoments(pc.readSet, q);
        h.mean += w * m.mean;
        h.square += w * (m.variance + m.mean * m.mean);
      }
      h.frames += w * direct.a;
      weights += w;
    }
  // Too little of the footprint survives: start over rather than trust one corner.
  if (weights < 0.01) return History(vec3(0.0), vec3(0.0), vec2(0.0), vec2(0.0), 0.0);
  h.direct /= weights;
  h.indirect /= weights;
  h.mean /= weights;
  h.square /= weights;
  h.frames /= weights;
  return h;
}

// FrameStats::accumulatedFrames: the pixel's history length (this frame included) in GiCounters' histogram,
// for one row in GI_HISTORY_ROW_STEP; a subgroup whose lanes agree adds them with one atomic.
void countHistory(ivec2 p, float frames) {
  if (p.y % int(GI_HISTORY_ROW_STEP) != 0) return;
  const uint bin = min(uint(frames + 0.5), GI_HISTORY_BINS - 1u);
  if (subgroupAllEqual(bin)) {
    const uint lanes = subgroupAdd(1u);
    if (subgroupElect()) atomicAdd(giCounters.historyFrames[bin], lanes);
  } else {
    atomicAdd(giCounters.historyFrames[bin], 1u);
  }
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  const float noisyAlpha = imageLoad(giNoisyIndirect, p).a;  // sspsf's filter-vertex flag, kept
  if (!giGbCovered(p)) {
    write(p, vec3(0.0), vec3(0.0), 0.0, GiMoments(vec2(0.0), vec2(0.0)), noisyAlpha);
    return;
  }
  vec3 dir;
  const vec3 world = giGbPosition(p, dir);
  const vec3 n = giGbNormal(p);
  const float depth = giGbViewDepth(p);
  // Emission is exact in every frame: only the reflected direct light is
  // accumulated (a bright emitter would bleed into its neighbours through the
  // bilinear history taps).
  const vec3 emission = giGbEmission(p);
  // Direct light is accumulated demodulated by the base colour (SVGF §4): the
  // history then carries light, not texture, and bilinear taps under motion
  // do not smear the texture; this frame's base colour puts it back.
  const vec3 albedo = giDirectAlbedo(p);
  vec3 direct, indirect;
  giNewFrameLight(p, direct, indirect);
  History h = reproject(p, n, depth, world);
  if (pc.historyClamp > 0.0 && h.frames > 0.0) {
    // The history clamp: what this frame's samples around the pixel cannot have come from is scaled back.
    // Nine equal samples (at 1 spp most often nine paths that all found no light) say nothing of the
    // spread: a band of width 0 would hold the history at their value, black where light is rare.
    const vec4 spread = imageLoad(giTemporalSpread, p);
    if (spread.y > 0.0) h.direct = giClampLuminance(h.direct, GiLuminanceSpread(spread.x, spread.y), pc.historyClamp);
    if (spread.w > 0.0)
      h.indirect = giClampLuminance(h.indirect, GiLuminanceSpread(spread.z, spread.w), pc.historyClamp);
  }
  const float lumDirect = giLuminance(direct), lumIndirect = giLuminance(indirect);
  const vec2 luminance = vec2(lumDirect, lumIndirect);
  if (h.frames == 0.0) {  // no history: this frame's light stands as the trace wrote it
    countHistory(p, 1.0);
    write(p, direct, indirect, 1.0, GiMoments(luminance, vec2(0.0)), noisyAlpha);
    return;
  }
  float frames = h.frames + 1.0;
  const float blend = max(1.0 / frames, pc.minBlend), momentsBlend = max(1.0 / frames, pc.momentsMinBlend);
  const vec2 lambda = pc.gradients != 0u ? giTemporalLambda(p) : vec2(0.0);  // direct, indirect
  const vec2 blends = mix(vec2(blend), vec2(1.0), lambda);
  // One history count serves both: where light changed it drops to the shorter history's.
  if (max(lambda.x, lambda.y) > 0.0) frames = min(frames, 1.0 / max(blends.x, blends.y));
  const vec3 outDirect = pc.direct != 0u ? mix(h.direct, direct, blends.x) : direct;
  const vec3 outIndirect = pc.directOnly != 0u ? indirect : mix(h.indirect, indirect, blends.y);
  const vec2 momentsBlends = mix(vec2(momentsBlend), vec2(1.0), lambda);
  // The moments' running mean and mean square, kept as the mean and the variance about it:
  // σ²' = (1 − a)·(σ² + a·(l − μ)²), exactly what E[l²]' − E[l]'² gives.
  const vec2 variance = max(vec2(0.0), h.square - h.mean * h.mean), deviation = luminance - h.mean;
  const GiMoments moments = GiMoments(mix(h.mean, luminance, momentsBlends),
                                      (1.0 - momentsBlends) * (variance + momentsBlends * deviation * deviation));
  write(p, outDirect, outIndirect, min(frames, 65536.0), moments, noisyAlpha);
  countHistory(p, frames);
  if (pc.directOnly != 0u) giStoreDirectAndFrames(p, emission + albedo * outDirect, min(frames, 63.0));
  else if (pc.direct != 0u) giStoreDirect(p, emission + albedo * outDirect);
  if (pc.directOnly != 0u) return;
  if (pc.indirectOutput != 0u) giStoreIndirect(p, outIndirect);  // raw's result; a filter that follows overwrites it
  if (pc.noisyOutput != 0u) giStoreNoisy(p, outIndirect, noisyAlpha);
}
