#version 460
// Edge-avoiding à-trous wavelet filter (Dammertz et al. 2010), the guided
// filter's second baseline: a 5×5 B3-spline kernel whose taps spread 2^i
// pixels apart in iteration i, weighted by colour, normal and position edge
// stops. The colour stop halves every iteration, as in the paper.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { AtrousPush pc; };

vec4 loadSource(ivec2 q) {
  if (pc.source == 0u) return imageLoad(filterInput, q);
  if (pc.source == 1u) return vec4(filterLoadOutput(q, pc.encoding), 1.0);
  return imageLoad(filterTemp, q);
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = filterSize();
  if (any(greaterThanEqual(p, size))) return;
  const float kernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
  vec4 centre = loadSource(p);
  vec4 pc0 = imageLoad(filterPosition, p);
  vec3 result = centre.rgb;
  if (pc0.w > 0.0) {
    vec3 nc = imageLoad(filterGuidance, p).xyz;
    int step = 1 << pc.iteration;
    float sigmaColor = pc.sigmaColor / float(1 << pc.iteration);
    float invColor = 1.0 / max(sigmaColor * sigmaColor, 1e-30);
    float invNormal = 1.0 / max(pc.sigmaNormal * pc.sigmaNormal, 1e-30);
    float sigmaPosition = pc.sigmaPosition * pc0.w;  // relative to the view depth: scale-free
    float invPosition = 1.0 / max(sigmaPosition * sigmaPosition, 1e-30);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        ivec2 q = p + ivec2(dx, dy) * step;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
        vec4 pq = imageLoad(filterPosition, q);
        if (pq.w <= 0.0) continue;
        vec3 c = loadSource(q).rgb;
        vec3 dc = c - centre.rgb, dn = imageLoad(filterGuidance, q).xyz - nc, dx3 = pq.xyz - pc0.xyz;
        float w = kernel[abs(dx)] * kernel[abs(dy)] *
                  exp(-dot(dc, dc) * invColor - dot(dn, dn) * invNormal - dot(dx3, dx3) * invPosition);
        sum += w * c;
        weightSum += w;
      }
    result = sum / max(weightSum, 1e-30);
  }
  if (pc.destination == 1u) filterStoreOutput(p, result, pc.encoding);
  else imageStore(filterTemp, p, vec4(result, 1.0));
}
