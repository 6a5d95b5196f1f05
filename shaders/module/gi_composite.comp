#version 460
// The module's last pass: the filter clamp (temporal.glsl) on what the method
// filtered, then direct + diffuse albedo × demodulated indirect, or the debug
// view the settings pick. AAF adds its glossy receivers' specular term. In the
// indirect-only mode (gi::Settings::indirectOnly) the direct output is 0.
// The hash methods' packed direct history is also stored here
// (storePackedHistory: the first pass after the temporal pass has read it),
// and the other methods' history guide (GiCompositePush::writesGuide).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lights.glsl"
#include "gi_frame.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiCompositePush pc; };

// Last frame's history length at p, as the temporal pass left it (0 without one).
float historyFramesAt(ivec2 p) {
  return pc.packedHistory != 0u     ? imageLoad(giOutDirect, p).a
         : pc.temporalWritten == 2u ? 0.0
         : pc.svgfFrames != 0u      ? giLoadSvgfFrames(pc.temporalWritten, p)
         : pc.temporalWritten == 0u ? imageLoad(giHistoryDirectA, p).a
         : pc.temporalWritten == 1u ? imageLoad(giHistoryDirectB, p).a
                                    : 0.0;
}

// The hash methods' direct history (GI_BINDING_HISTORY_PACKED) is stored here, not by the temporal pass:
// that pass reads its neighbours' texels bilinearly, so each texel is replaced only once every neighbour
// has read it, and this is the first pass after it. This frame's accumulated direct light over the base
// colour, the pixel's guide and its frames; the direct output's alpha, which carried the frames, back to 1.
void storePackedHistory(ivec2 p, vec3 direct, float historyFrames) {
  uvec2 texel = uvec2(0u);  // no surface: no history
  if (giGbCovered(p))
    texel = giPackHistory(GiPackedHistory((direct - giGbEmission(p)) / giDirectAlbedo(p) * pc.historyScale,
                                          vec4(giGbNormal(p), giGbViewDepth(p) / giFrame.depthScale), historyFrames));
  imageStore(giHistoryPacked, p, uvec4(texel, 0u, 0u));
  giStoreDirect(p, direct);
}

// The image the filter read at p: the noisy indirect, or the indirect history written this frame (its alpha
// the filter-vertex flag either way).
vec4 filterInput(ivec2 p) {
  if ((pc.clampLight & GI_CLAMP_FROM_HISTORY) == 0u) return imageLoad(giNoisyIndirect, p);
  return giLoadHistoryIndirect(pc.temporalWritten, p);
}

// The filter clamp (TemporalSettings::filterClamp) on what the method filtered, against svgf's first
// luminance moments (the set written this frame) or the noisy image the filter read. Only where the
// history is long enough to speak for itself (a few samples' spread says little: nine 1-spp samples that
// all missed the light would hold the filter at black).
void applyFilterClamp(ivec2 p, float historyFrames, bool indirectOnly, inout vec3 direct, inout vec3 indirect) {
  const bool clamped = pc.filterClamp > 0.0 && pc.clampLight != 0u && giHistoryTrusted(historyFrames) &&
                       giGbCovered(p) &&
                       ((pc.clampLight & GI_CLAMP_FILTER_VERTICES) == 0u || filterInput(p).a > 0.5);
  if (!clamped) return;
  GiLuminanceSpread indirectSpread, directSpread;
  uint source = GI_SPREAD_NOISY;
  if ((pc.clampLight & GI_CLAMP_FROM_MOMENTS) != 0u) source = GI_SPREAD_MOMENTS;
  if ((pc.clampLight & GI_CLAMP_FROM_HISTORY) != 0u) source = GI_SPREAD_HISTORY;
  giNeighbourhoodSpread(p, source, pc.temporalWritten, directSpread, indirectSpread);
  if ((pc.clampLight & GI_CLAMP_INDIRECT) != 0u) {
    indirect = giClampLuminance(indirect, indirectSpread, pc.filterClamp);
    giStoreIndirect(p, indirect);
  }
  if ((pc.clampLight & GI_CLAMP_DIRECT) != 0u && !indirectOnly) {
    const vec3 emission = giGbEmission(p), albedo = giDirectAlbedo(p);
    direct = emission + albedo * giClampLuminance((direct - emission) / albedo, directSpread, pc.filterClamp);
    giStoreDirect(p, direct);
  }
}

// The lit image: direct + diffuse albedo × demodulated indirect (aaf_ao: ambient occlusion), with AAF's
// glossy receivers' specular term.
vec3 litImage(ivec2 p, vec3 direct, vec3 indirect) {
  // aaf_ao: the indirect image holds occlusion (reflectors radiate 1); AO = 1 − occlusion.
  if (pc.ambientOcclusion != 0u) return vec3(1.0) - clamp(indirect, 0.0, 1.0);
  // Filters may overshoot below zero; radiance cannot.
  vec3 result = direct + giGbDiffuseAlbedo(p) * max(indirect, vec3(0.0));
  // AAF on glossy receivers: f0 applied after filtering (bsdf.glsl's split of Schlick's Fresnel).
  if (pc.aafSpecular != 0u)
    result += max(giGbSpecularF0(p) * imageLoad(giAafGlossy, p).rgb + imageLoad(giAafGlossyEdge, p).rgb, vec3(0.0));
  return result;
}

// What the composite output shows: the lit image, or the debug view the settings pick.
vec3 composite(ivec2 p, vec3 direct, vec3 indirect, float historyFrames) {
  switch (pc.debugView) {
    case GI_DEBUG_DIRECT: return direct;
    case GI_DEBUG_INDIRECT: return indirect;
    case GI_DEBUG_ALBEDO: return giGbAlbedo(p).rgb;
    case GI_DEBUG_NORMAL: return giGbCovered(p) ? giGbNormal(p) * 0.5 + 0.5 : vec3(0.5);
    case GI_DEBUG_GUIDANCE: return imageLoad(giGuidance, p).xyz;
    case GI_DEBUG_GUIDANCE_DEPTH: return vec3(imageLoad(giGuidance, p).w);
    case GI_DEBUG_FILTER_IN_OUT: return p.x < int(giFrame.size.x / 2u) ? giLoadNoisy(p) : indirect;
    case GI_DEBUG_GIF_COEFFICIENTS: return vec3(imageLoad(giDebug, p).rg, 0.0);
    // AAF maps (Mehta et al. Fig. 6f–g): distances over the scene extent, samples over 100, width over 32 px.
    case GI_DEBUG_AAF_ZMIN: return vec3(imageLoad(giAafParams, p).x / pc.sceneExtent);
    case GI_DEBUG_AAF_ZMAX: return vec3(imageLoad(giAafParams, p).y / pc.sceneExtent);
    case GI_DEBUG_AAF_SAMPLES: return vec3(imageLoad(giAafParams, p).z / 100.0);
    case GI_DEBUG_AAF_FILTER_WIDTH: {
      float depth = giGbViewDepth(p);
      return vec3(depth > 0.0 ? imageLoad(giAafParams, p).w / (depth * pc.pixelScale) / 32.0 : 0.0);
    }
    // Hash map views (the lookup pass leaves key, LOD, samples, found in the debug image).
    case GI_DEBUG_HASH_CELLS: {
      uint key = uint(imageLoad(giDebug, p).x);
      return key == 0u ? vec3(0.0) : vec3(uvec3(key, key >> 8u, key >> 16u) & 255u) / 255.0;
    }
    case GI_DEBUG_HASH_LOD: return vec3(clamp((imageLoad(giDebug, p).y + 12.0) / 16.0, 0.0, 1.0));
    case GI_DEBUG_HASH_SAMPLES: return vec3(imageLoad(giDebug, p).z / 100.0);
    case GI_DEBUG_HASH_FOUND: {
      float f = imageLoad(giDebug, p).w;
      return f == 1.0 ? vec3(0.0, 1.0, 0.0) : f > 0.0 ? vec3(1.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    }
    case GI_DEBUG_HASH_OCCUPANCY: {
      float f = clamp(imageLoad(giDebug, p).w, 0.0, 1.0);
      return giGbCoveredRaw(p) ? vec3(f, 1.0 - f, 0.0) : vec3(0.0);
    }
    case GI_DEBUG_CONTINUATION_DEPTH: return vec3(clamp(imageLoad(giDebug, p).x, 0.0, 1.0));
    case GI_DEBUG_TEMPORAL_HISTORY: return vec3(min(historyFrames, 32.0) / 32.0);
    // svgf: the variance estimate before the à-trous iterations, and the history behind it.
    case GI_DEBUG_SVGF_VARIANCE: {
      const vec4 v = imageLoad(giDebug, p);
      return vec3(v.x, v.y, min(v.z, 32.0) / 32.0);
    }
    // Temporal gradients: λ, the share of the history dropped (0 where the gradients are off).
    case GI_DEBUG_TEMPORAL_GRADIENT: return pc.gradients != 0u ? vec3(giTemporalLambda(p), 0.0) : vec3(0.0);
    default: return litImage(p, direct, indirect);
  }
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  vec3 direct = giLoadDirect(p);
  vec3 indirect = giLoadIndirect(p);
  const float historyFrames = historyFramesAt(p);
  if (pc.packedHistory != 0u) storePackedHistory(p, direct, historyFrames);
  if (pc.writesGuide != 0u) imageStore(giHistoryGuide, p, uvec4(giCurrentGuide(p)));
  const bool indirectOnly = giFrame.primaryDirect == GI_PRIMARY_DIRECT_NONE;  // the engine lights the primary hits
  if (indirectOnly) {
    direct = vec3(0.0);
    giStoreDirect(p, direct);
  }
  applyFilterClamp(p, historyFrames, indirectOnly, direct, indirect);
  if (GI_SCENE_HAS_SKY && pc.ambientOcclusion == 0u && !indirectOnly && !giGbCovered(p)) {
    // The background is the sky seen through the pixel's centre: the direct output holds it too.
    direct = giSkyRadiance(giCameraRayDirection(giFrame.camera, vec2(p) + 0.5));
    giStoreDirect(p, direct);
  }
  const vec3 result = composite(p, direct, indirect, historyFrames);
  // Radiance views carry the pre-exposure; the other views are pictures scaled to [0,1] for display,
  // stored as they are (a count past its scale reads above 1: tests count with them).
  if (pc.radiance != 0u) giStoreComposite(p, result);
  else imageStore(giOutComposite, p, vec4(result, 1.0));
  if (pc.packedOutputs != 0u) {  // the engine's outputs hold no sign: the stored light as it is, within range
    imageStore(giPackedDirect, p, vec4(clamp(imageLoad(giOutDirect, p).rgb, 0.0, pc.packedMax), 1.0));
    imageStore(giPackedIndirect, p, vec4(clamp(imageLoad(giOutIndirect, p).rgb, 0.0, pc.packedMax), 1.0));
  }
}
