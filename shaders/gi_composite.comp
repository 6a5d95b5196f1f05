#version 460
// The module's last pass: the filter clamp (temporal.glsl) on what the method
// filtered, then direct + diffuse albedo × demodulated indirect, or the debug
// view the settings pick. AAF adds its glossy receivers' specular term. In the
// indirect-only mode (gi::Settings::indirectOnly) the direct output is 0.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lights.glsl"
#include "gi_frame.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiCompositePush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  vec3 direct = giLoadDirect(p);
  vec3 indirect = giLoadIndirect(p);
  // Only where the history is long enough to speak for itself (a few samples' spread says little:
  // nine 1-spp samples that all missed the light would hold the filter at black).
  const float historyFrames = pc.packedHistory != 0u     ? imageLoad(giOutDirect, p).a
                              : pc.temporalWritten == 0u ? imageLoad(giHistoryDirectA, p).a
                              : pc.temporalWritten == 1u ? imageLoad(giHistoryDirectB, p).a
                                                         : 0.0;
  if (pc.packedHistory != 0u) {
    // The hash methods' direct history, now that the temporal pass has read every neighbour's texel:
    // this frame's accumulated direct light over the base colour, the pixel's guide and its frames.
    uvec2 texel = uvec2(0u);  // no surface: no history
    if (giGbCovered(p))
      texel = giPackHistory(GiPackedHistory((direct - giGbEmission(p)) / giDirectAlbedo(p) * pc.historyScale,
                                            vec4(giGbNormal(p), giGbViewDepth(p) / giFrame.depthScale), historyFrames));
    imageStore(giHistoryPacked, p, uvec4(texel, 0u, 0u));
    giStoreDirect(p, direct);  // the alpha back to 1
  }
  const bool indirectOnly = giFrame.primaryDirect == GI_PRIMARY_DIRECT_NONE;  // the engine lights the primary hits
  if (indirectOnly) {
    direct = vec3(0.0);
    giStoreDirect(p, direct);
  }
  const bool clamped = pc.filterClamp > 0.0 && pc.clampLight != 0u && historyFrames >= GI_TRUSTED_HISTORY &&
                       giGbCovered(p) &&
                       ((pc.clampLight & GI_CLAMP_FILTER_VERTICES) == 0u || imageLoad(giNoisyIndirect, p).a > 0.5);
  if (clamped) {
    // Against svgf's first luminance moments (the set written this frame), or the noisy image the filter read.
    GiLuminanceSpread indirectSpread, directSpread;
    giNeighbourhoodSpread(p, (pc.clampLight & GI_CLAMP_FROM_MOMENTS) != 0u ? GI_SPREAD_MOMENTS : GI_SPREAD_NOISY,
                          pc.temporalWritten, directSpread, indirectSpread);
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
  if (GI_SCENE_HAS_SKY && pc.ambientOcclusion == 0u && !indirectOnly && !giGbCovered(p)) {
    // The background is the sky seen through the pixel's centre: the direct output holds it too.
    direct = giSkyRadiance(giCameraRayDirection(giFrame.camera, vec2(p) + 0.5));
    giStoreDirect(p, direct);
  }
  vec3 result;
  switch (pc.debugView) {
    case GI_DEBUG_DIRECT: result = direct; break;
    case GI_DEBUG_INDIRECT: result = indirect; break;
    case GI_DEBUG_ALBEDO: result = giGbAlbedo(p).rgb; break;
    case GI_DEBUG_NORMAL: result = giGbCovered(p) ? giGbNormal(p) * 0.5 + 0.5 : vec3(0.5); break;
    case GI_DEBUG_GUIDANCE: result = imageLoad(giGuidance, p).xyz; break;
    case GI_DEBUG_GUIDANCE_DEPTH: result = vec3(imageLoad(giGuidance, p).w); break;
    case GI_DEBUG_FILTER_IN_OUT:
      result = p.x < int(giFrame.size.x / 2u) ? giLoadNoisy(p) : indirect;
      break;
    case GI_DEBUG_GIF_COEFFICIENTS: result = vec3(imageLoad(giDebug, p).rg, 0.0); break;
    // AAF maps (Mehta et al. Fig. 6f–g): distances over the scene extent, samples over 100, width over 32 px.
    case GI_DEBUG_AAF_ZMIN: result = vec3(imageLoad(giAafParams, p).x / pc.sceneExtent); break;
    case GI_DEBUG_AAF_ZMAX: result = vec3(imageLoad(giAafParams, p).y / pc.sceneExtent); break;
    case GI_DEBUG_AAF_SAMPLES: result = vec3(imageLoad(giAafParams, p).z / 100.0); break;
    case GI_DEBUG_AAF_FILTER_WIDTH: {
      float depth = giGbViewDepth(p);
      result = vec3(depth > 0.0 ? imageLoad(giAafParams, p).w / (depth * pc.pixelScale) / 32.0 : 0.0);
      break;
    }
    // Filters may overshoot below zero; radiance cannot.
    // Hash map views (the lookup pass leaves key, LOD, samples, found in the debug image).
    case GI_DEBUG_HASH_CELLS: {
      uint key = uint(imageLoad(giDebug, p).x);
      result = key == 0u ? vec3(0.0) : vec3(uvec3(key, key >> 8u, key >> 16u) & 255u) / 255.0;
      break;
    }
    case GI_DEBUG_HASH_LOD: result = vec3(clamp((imageLoad(giDebug, p).y + 12.0) / 16.0, 0.0, 1.0)); break;
    case GI_DEBUG_HASH_SAMPLES: result = vec3(imageLoad(giDebug, p).z / 100.0); break;
    case GI_DEBUG_HASH_FOUND: {
      float f = imageLoad(giDebug, p).w;
      result = f == 1.0 ? vec3(0.0, 1.0, 0.0) : f > 0.0 ? vec3(1.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
      break;
    }
    case GI_DEBUG_HASH_OCCUPANCY: {
      float f = clamp(imageLoad(giDebug, p).w, 0.0, 1.0);
      result = giGbCoveredRaw(p) ? vec3(f, 1.0 - f, 0.0) : vec3(0.0);
      break;
    }
    case GI_DEBUG_CONTINUATION_DEPTH: result = vec3(clamp(imageLoad(giDebug, p).x, 0.0, 1.0)); break;
    case GI_DEBUG_TEMPORAL_HISTORY: result = vec3(min(historyFrames, 32.0) / 32.0); break;
    // svgf: the variance estimate before the à-trous iterations, and the history behind it.
    case GI_DEBUG_SVGF_VARIANCE: {
      const vec4 v = imageLoad(giDebug, p);
      result = vec3(v.x, v.y, min(v.z, 32.0) / 32.0);
      break;
    }
    // Temporal gradients: λ, the share of the history dropped (0 where the gradients are off).
    case GI_DEBUG_TEMPORAL_GRADIENT: result = pc.gradients != 0u ? vec3(giTemporalLambda(p), 0.0) : vec3(0.0); break;
    default:
      // aaf_ao: the indirect image holds occlusion (reflectors radiate 1); AO = 1 − occlusion.
      result = pc.ambientOcclusion != 0u ? vec3(1.0) - clamp(indirect, 0.0, 1.0)
                                         : direct + giGbDiffuseAlbedo(p) * max(indirect, vec3(0.0));
      // AAF on glossy receivers: f0 applied after filtering (bsdf.glsl's split of Schlick's Fresnel).
      if (pc.aafSpecular != 0u && pc.ambientOcclusion == 0u)
        result += max(giGbSpecularF0(p) * imageLoad(giAafGlossy, p).rgb + imageLoad(giAafGlossyEdge, p).rgb, vec3(0.0));
      break;
  }
  // Radiance views carry the pre-exposure; the other views are pictures scaled to [0,1] for display,
  // stored as they are (a count past its scale reads above 1: tests count with them).
  if (pc.radiance != 0u) giStoreComposite(p, result);
  else imageStore(giOutComposite, p, vec4(result, 1.0));
}
