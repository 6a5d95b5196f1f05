#version 460
// One of SVGF's à-trous iterations (Schied et al. 2017 §4.3): a 5×5
// B3-spline kernel whose taps lie 2^i pixels apart, weighted by depth,
// normal and a luminance stop scaled by the standard deviation the variance
// estimate gives (3×3-blurred), separately for direct and indirect light;
// the variance is filtered with the squared weights. The first iteration's
// light becomes the history the next frame reprojects (§4.4); the last one's
// goes to the outputs (direct remodulated by the base colour, plus emission).
// The images they read and write: svgf.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "svgf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiSvgfPush pc; };

// The pair this iteration reads; it writes the other, the last one the outputs (remodulated).
uint readPair() { return svgfReadPair(pc.iteration, pc.iterations); }
SvgfTexel load(ivec2 q) { return svgfLoad(readPair(), pc.writtenSet, q); }

// The variances at p blurred by a 3×3 Gaussian (§4.3: it steadies the luminance stop).
vec2 blurredVariance(ivec2 p) {
  const float k[2] = float[2](0.5, 0.25);  // (1/4, 1/2, 1/4) per axis
  vec2 sum = vec2(0.0), weights = vec2(0.0);
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const ivec2 q = p + ivec2(i, j);
      if (svgfGuide(q, true).w <= 0.0) continue;
      const float w = k[abs(i)] * k[abs(j)];
      const SvgfTexel t = load(q);
      sum += w * vec2(t.direct.a, t.indirect.a);
      weights += w;
    }
  return sum / max(weights, vec2(1e-30));
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  const vec4 guide = svgfGuide(p, true);
  const float z = guide.w;
  if (z <= 0.0) return;  // no surface: the outputs keep what the trace wrote, and no tap reads it
  const SvgfTexel centre = load(p);
  const vec2 gradient = svgfDepthGradient(p, z, true);
  const vec2 sigma = pc.sigmaLuminance * sqrt(blurredVariance(p)) + 1e-10;
  const float lDirect = giLuminance(centre.direct.rgb), lIndirect = giLuminance(centre.indirect.rgb);
  const float kernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
  const int step = 1 << pc.iteration;
  vec4 sumDirect = vec4(0.0), sumIndirect = vec4(0.0);
  vec2 weights = vec2(0.0);
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      const ivec2 q = p + step * ivec2(i, j);
      const vec4 tap = svgfGuide(q, true);
      if (tap.w <= 0.0) continue;
      const SvgfTexel t = load(q);
      const float h = kernel[abs(i)] * kernel[abs(j)];
      const float geometry = i == 0 && j == 0 ? 1.0
                                              : svgfGeometryWeight(guide, gradient, tap, vec2(step * ivec2(i, j)),
                                                                   pc.sigmaDepth, pc.sigmaNormal);
      const vec2 w = h * geometry *
                     exp(-vec2(abs(lDirect - giLuminance(t.direct.rgb)), abs(lIndirect - giLuminance(t.indirect.rgb))) /
                         sigma);
      // Light with the weights, variance with their squares (eq. 2's variance).
      sumDirect += vec4(w.x * t.direct.rgb, w.x * w.x * t.direct.a);
      sumIndirect += vec4(w.y * t.indirect.rgb, w.y * w.y * t.indirect.a);
      weights += w;
    }
  const SvgfTexel filtered = SvgfTexel(vec4(sumDirect.rgb / weights.x, sumDirect.a / (weights.x * weights.x)),
                                       vec4(sumIndirect.rgb / weights.y, sumIndirect.a / (weights.y * weights.y)));
  if (pc.iteration == 0u) {  // feedback: the next frame reprojects this
    // Unfiltered direct light is already in the history as the temporal pass stored it.
    if (pc.writtenSet == 0u) {
      if (pc.direct != 0u) giStoreHistoryDirectA(p, filtered.direct.rgb, imageLoad(giHistoryDirectA, p).a);
      giStoreHistoryIndirectA(p, filtered.indirect.rgb, imageLoad(giHistoryIndirectA, p).a);  // the moment kept
    } else {
      if (pc.direct != 0u) giStoreHistoryDirectB(p, filtered.direct.rgb, imageLoad(giHistoryDirectB, p).a);
      giStoreHistoryIndirectB(p, filtered.indirect.rgb, imageLoad(giHistoryIndirectB, p).a);
    }
  }
  if (pc.iteration + 1u < pc.iterations) {
    svgfStore(readPair() == SVGF_OUTPUTS ? SVGF_SCRATCH : SVGF_OUTPUTS, pc.writtenSet, p, filtered, pc.direct);
    return;
  }
  if (pc.direct != 0u) giStoreDirect(p, giGbEmission(p) + giDirectAlbedo(p) * filtered.direct.rgb);
  giStoreIndirect(p, filtered.indirect.rgb);
}
