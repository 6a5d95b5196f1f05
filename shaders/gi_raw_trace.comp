#version 460
// Method `raw`: N unfiltered paths per pixel from the G-buffer's primary hit
// (path.glsl), direct and demodulated indirect kept apart, optionally averaged
// over frames while nothing changes (a running mean capped at maxHistory).
// With temporal gradients (temporal.glsl) every pixel keeps its first path's
// luminances and random state, and each tile's gradient pixel traces its
// first path with the random state its reprojected pixel used last frame.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "path.glsl"
#include "gi_frame.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiRawPush pc; };

// Gradient samples: last frame's (read) and this frame's (written) sets.
uvec4 giPreviousGradientSample(ivec2 q) {
  return pc.parity == 0u ? imageLoad(giGradientSamplesA, q) : imageLoad(giGradientSamplesB, q);
}
void giStoreGradientSample(ivec2 p, vec2 luminance, uint state) {
  const uvec4 v = uvec4(floatBitsToUint(luminance), state, 0u);
  if (pc.parity == 0u) imageStore(giGradientSamplesB, p, v);
  else imageStore(giGradientSamplesA, p, v);
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;  // for path space filtering (sspsf): the primary vertex has a diffuse lobe
    // Gradients: this pixel's first sample (luminances, random state) and, for a tile's gradient
    // pixel with a source, the change against its source's first sample last frame.
    const bool gradientPixel = pc.gradients == 2u && giGradientPixel(giGradientTile(p), giFrame.frameIndex, pc.seed) == p;
    vec2 first = vec2(0.0);
    uint firstState = 0u;
    vec4 gradient = vec4(0.0);
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      filterVertex = giHasDiffuseLobe(s.material);
      ivec2 q;
      const bool resample = gradientPixel && giGradientSource(p, pc.parity, pc.depthTolerance, pc.cosNormalLimit, q);
      const uvec4 source = resample ? giPreviousGradientSample(q) : uvec4(0u);
      float kept = 0.0;
      for (uint i = 0u; i < pc.samplesPerPixel; ++i) {
        GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex * pc.samplesPerPixel + i, pc.seed, GI_STREAM_MODULE);
        if (i == 0u && resample) rng.state = source.z;
        if (i == 0u) firstState = rng.state;
        GiPathSample path = giTracePathFromSurface(s, V, pc.maxBounces, pc.russianRouletteStart, rng);
        const bool keep = giKeepSample(path.direct, path.indirectDemod);
        if (i == 0u && keep) first = vec2(giLuminance(path.direct / giDirectAlbedo(p)), giLuminance(path.indirectDemod));
        if (!keep) continue;
        kept += 1.0;
        direct += path.direct;
        indirect += path.indirectDemod;
      }
      if (resample) {
        const vec2 now = first, then = uintBitsToFloat(source.xy);
        gradient = vec4(now.x - then.x, max(now.x, then.x), now.y - then.y, max(now.y, then.y));
      }
      float inv = 1.0 / max(kept, 1.0);
      direct = s.material.emission + direct * inv;
      indirect *= inv;
    }
    if (pc.gradients != 0u) {
      giStoreGradientSample(p, first, firstState);
      if (gradientPixel) imageStore(giTemporalGradient, giGradientTile(p), gradient);
    }
    if (pc.accumulate != 0u) {
      // Running mean: weight 1/(n+1) until the cap, then an exponential average.
      float n = float(min(pc.historyLength, pc.maxHistory - 1u));
      float w = 1.0 / (n + 1.0);
      if (pc.historyLength > 0u) {
        direct = mix(imageLoad(giHistoryDirect, p).rgb, direct, w);
        indirect = mix(imageLoad(giHistoryIndirect, p).rgb, indirect, w);
      }
      imageStore(giHistoryDirect, p, vec4(direct, 1.0));
      imageStore(giHistoryIndirect, p, vec4(indirect, 1.0));
    }
    giStoreDirect(p, direct);
    giStoreIndirect(p, indirect);   // filters overwrite this one
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  giCountRays(inside);
}
