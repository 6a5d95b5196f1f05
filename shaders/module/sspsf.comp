#version 460
// Screen-space path filtering (Meijer 2019 §4.1): each pixel averages the
// demodulated radiance arriving at the filter vertices of a window of
// neighbours, weighted by world-position similarity (a Gaussian whose σ is
// half the HPSF cell for the same filter width) and gated by normal
// similarity. Only filter vertices take part (the input's alpha: the primary
// vertex has a diffuse lobe, the rule hpsf follows too); other pixels, and
// background, neither filter nor contribute.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { SspsfPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = filterSize();
  if (any(greaterThanEqual(p, size))) return;
  vec4 x = imageLoad(filterPosition, p);
  vec4 own = imageLoad(filterInput, p);
  vec3 result = own.rgb;
  if (x.w > 0.0 && own.a > 0.0) {
    vec3 n = imageLoad(filterGuidance, p).xyz * 2.0 - 1.0;
    float sigma = 0.5 * pc.filterWidth * pc.pixelAngle * x.w;
    float inv = 0.5 / max(sigma * sigma, 1e-30);
    int half_ = int(pc.window / 2u);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    for (int dy = -half_; dy <= half_; ++dy)
      for (int dx = -half_; dx <= half_; ++dx) {
        ivec2 q = p + ivec2(dx, dy);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
        vec4 y = imageLoad(filterPosition, q);
        vec4 v = imageLoad(filterInput, q);
        if (y.w <= 0.0 || v.a <= 0.0) continue;
        vec3 nq = imageLoad(filterGuidance, q).xyz * 2.0 - 1.0;
        if (dot(n, nq) < pc.cosNormal * length(n) * length(nq)) continue;
        vec3 d = y.xyz - x.xyz;
        float w = exp(-dot(d, d) * inv);
        sum += w * v.rgb;
        weightSum += w;
      }
    result = sum / max(weightSum, 1e-30);
  }
  filterStoreOutput(p, result, pc.encoding);
}
