#version 460
// One of SVGF's à-trous iterations (Schied et al. 2017 §4.3): a 5×5
// B3-spline kernel whose taps lie 2^i pixels apart, weighted by depth,
// normal and a luminance stop scaled by the standard deviation the variance
// estimate gives (3×3-blurred), separately for direct and indirect light;
// the variance is filtered with the squared weights. The first iteration's
// light becomes the history the next frame reprojects (§4.4); the last one's
// goes to the outputs (direct remodulated by the base colour, plus emission).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "svgf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiSvgfPush pc; };

bool fromPing() { return (pc.iteration & 1u) == 0u; }
vec4 loadDirect(ivec2 q) { return fromPing() ? imageLoad(giSvgfDirectPing, q) : imageLoad(giSvgfDirectPong, q); }
vec4 loadIndirect(ivec2 q) { return fromPing() ? imageLoad(giSvgfIndirectPing, q) : imageLoad(giSvgfIndirectPong, q); }
void store(ivec2 p, vec4 direct, vec4 indirect) {
  if (fromPing()) {
    imageStore(giSvgfDirectPong, p, direct);
    imageStore(giSvgfIndirectPong, p, indirect);
  } else {
    imageStore(giSvgfDirectPing, p, direct);
    imageStore(giSvgfIndirectPing, p, indirect);
  }
}

// The variances at p blurred by a 3×3 Gaussian (§4.3: it steadies the luminance stop).
vec2 blurredVariance(ivec2 p) {
  const float k[2] = float[2](0.5, 0.25);  // (1/4, 1/2, 1/4) per axis
  vec2 sum = vec2(0.0), weights = vec2(0.0);
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const ivec2 q = p + ivec2(i, j);
      if (svgfGuide(q).w <= 0.0) continue;
      const float w = k[abs(i)] * k[abs(j)];
      sum += w * vec2(loadDirect(q).a, loadIndirect(q).a);
      weights += w;
    }
  return sum / max(weights, vec2(1e-30));
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(gl_GlobalInvocationID.xy, giFrame.size))) return;
  const vec4 guide = svgfGuide(p);
  const float z = guide.w;
  const vec4 centreDirect = loadDirect(p), centreIndirect = loadIndirect(p);
  vec4 outDirect = centreDirect, outIndirect = centreIndirect;
  if (z > 0.0) {
    const vec2 gradient = svgfDepthGradient(p, z);
    const vec2 sigma = pc.sigmaLuminance * sqrt(blurredVariance(p)) + 1e-10;
    const float lDirect = giLuminance(centreDirect.rgb), lIndirect = giLuminance(centreIndirect.rgb);
    const float kernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
    const int step = 1 << pc.iteration;
    vec4 sumDirect = vec4(0.0), sumIndirect = vec4(0.0);
    vec2 weights = vec2(0.0);
    for (int j = -2; j <= 2; ++j)
      for (int i = -2; i <= 2; ++i) {
        const ivec2 q = p + step * ivec2(i, j);
        const vec4 tap = svgfGuide(q);
        if (tap.w <= 0.0) continue;
        const vec4 d = loadDirect(q), ind = loadIndirect(q);
        const float h = kernel[abs(i)] * kernel[abs(j)];
        const float geometry = i == 0 && j == 0 ? 1.0
                                                : svgfGeometryWeight(guide, gradient, tap, vec2(step * ivec2(i, j)),
                                                                     pc.sigmaDepth, pc.sigmaNormal);
        const vec2 w = h * geometry *
                       exp(-vec2(abs(lDirect - giLuminance(d.rgb)), abs(lIndirect - giLuminance(ind.rgb))) / sigma);
        // Light with the weights, variance with their squares (eq. 2's variance).
        sumDirect += vec4(w.x * d.rgb, w.x * w.x * d.a);
        sumIndirect += vec4(w.y * ind.rgb, w.y * w.y * ind.a);
        weights += w;
      }
    outDirect = vec4(sumDirect.rgb / weights.x, sumDirect.a / (weights.x * weights.x));
    outIndirect = vec4(sumIndirect.rgb / weights.y, sumIndirect.a / (weights.y * weights.y));
  }
  if (pc.direct == 0u) outDirect = centreDirect;  // exact (punctual lights only): not filtered
  store(p, outDirect, outIndirect);
  if (pc.iteration == 0u && z > 0.0) {  // feedback: the next frame reprojects this
    // Unfiltered direct light is already in the history as the temporal pass stored it.
    if (pc.parity == 0u) {
      if (pc.direct != 0u) giStoreHistoryDirect(p, outDirect.rgb, imageLoad(giHistoryDirect, p).a);
      giStoreHistoryIndirect(p, outIndirect.rgb, 1.0);
    } else {
      if (pc.direct != 0u) giStoreHistoryDirectB(p, outDirect.rgb, imageLoad(giHistoryDirectB, p).a);
      giStoreHistoryIndirectB(p, outIndirect.rgb, 1.0);
    }
  }
  if (pc.last != 0u && z > 0.0) {
    if (pc.direct != 0u) giStoreDirect(p, giGbEmission(p) + giDirectAlbedo(p) * outDirect.rgb);
    giStoreIndirect(p, outIndirect.rgb);
  }
}
