#version 460
// Method `raw`: N unfiltered paths per pixel from the G-buffer's primary hit
// (path.glsl), direct and demodulated indirect kept apart, optionally averaged
// over frames while nothing changes (a running mean capped at maxHistory).
// With temporal gradients (temporal.glsl) every pixel keeps its first path's
// luminances and random state for gi_temporal_gradient.comp next frame.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "path_task.glsl"
#include "gi_frame.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiRawPush pc; };

// Temporal gradients: this frame's first samples go to the set the temporal pass writes.
void giStoreGradientSample(ivec2 p, vec2 luminance, uint state, uvec2 pick) {
  const uvec4 v = uvec4(giPackGradientLuminance(luminance), state, pick);
  if (pc.readSet == 0u) imageStore(giGradientSamplesB, p, v);
  else imageStore(giGradientSamplesA, p, v);
}

// Raw's still-camera running mean, kept in the radiance histories' set A (raw runs no temporal pass):
// this frame's light takes weight w.
void runningMean(ivec2 p, float w, inout vec3 direct, inout vec3 indirect) {
  direct = mix(giLoadHistoryDirectA(p).rgb, direct, w);
  indirect = mix(giLoadHistoryIndirectA(p).rgb, indirect, w);
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;  // for path space filtering (sspsf): the primary vertex has a diffuse lobe
    // Temporal gradients: this pixel's first sample (luminances, random state), kept for the next frame.
    vec2 first = vec2(0.0);
    uint firstState = 0u;
    uvec2 reservoir = GI_NO_RESERVOIR;
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      filterVertex = giHasDiffuseLobe(s.material);
      float kept = 0.0;
      reservoir = giPrimaryReservoir(p);
      for (uint i = 0u; i < pc.samplesPerPixel; ++i) {
        GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex * pc.samplesPerPixel + i, pc.seed, GI_STREAM_MODULE);
        if (i == 0u) firstState = rng.state;
        GiPathSample path = giTracePathFromSurface(s, V, pc.maxBounces, pc.russianRouletteStart, reservoir, rng);
        const bool keep = giKeepSample(path.direct, path.indirectDemod);
        if (i == 0u && keep) first = giGradientLuminance(path.direct, path.indirectDemod, p);  // temporal.glsl
        if (!keep) continue;
        kept += 1.0;
        direct += path.direct;
        indirect += path.indirectDemod;
      }
      float inv = 1.0 / max(kept, 1.0);
      direct = s.material.emission + direct * inv;
      indirect *= inv;
    }
    if (pc.gradients != 0u) giStoreGradientSample(p, first, firstState, giUsesReservoir(reservoir) ? reservoir : uvec2(GI_RESERVOIR_EMPTY, 0u));
    if (pc.accumulate != 0u) {
      // Running mean: weight 1/(n+1) until the cap, then an exponential average.
      float n = float(min(pc.historyLength, pc.maxHistory - 1u));
      float w = 1.0 / (n + 1.0);
      if (pc.historyLength > 0u) runningMean(p, w, direct, indirect);
      giStoreHistoryDirectA(p, direct, 1.0);  // the running mean lives in the radiance histories' set A
      giStoreHistoryIndirectA(p, indirect, 1.0);
    }
    giStoreDirect(p, direct);
    giStoreIndirect(p, indirect);   // filters overwrite this one
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  giCountRays(inside);
}
