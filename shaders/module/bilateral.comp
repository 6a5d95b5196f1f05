#version 460
// Joint (cross) bilateral filter, the guided filter's first baseline
// (Bauszat et al. 2011, §5): a spatial Gaussian times Gaussians on the
// difference in normal and in depth. Cost grows with radius².
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { BilateralPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = filterSize();
  if (any(greaterThanEqual(p, size))) return;
  vec4 gc = imageLoad(filterGuidance, p);
  if (gc.w <= 0.0) {  // background (depth 0): nothing to filter
    filterStoreOutput(p, imageLoad(filterInput, p).rgb, pc.encoding);
    return;
  }
  int r = int(pc.radius);
  float invSpatial = 0.5 / (pc.sigmaSpatial * pc.sigmaSpatial);
  float invNormal = 0.5 / (pc.sigmaNormal * pc.sigmaNormal);
  float depthScale = pc.sigmaDepth * max(gc.w, 1e-6);
  float invDepth = 0.5 / (depthScale * depthScale);
  vec3 sum = vec3(0.0);
  float weightSum = 0.0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      const vec4 g = imageLoad(filterGuidance, q);
      if (g.w <= 0.0) continue;  // background
      vec3 dn = g.xyz - gc.xyz;
      float dz = g.w - gc.w;
      float w = exp(-float(dx * dx + dy * dy) * invSpatial - dot(dn, dn) * invNormal - dz * dz * invDepth);
      sum += w * imageLoad(filterInput, q).rgb;
      weightSum += w;
    }
  filterStoreOutput(p, sum / max(weightSum, 1e-30), pc.encoding);
}
