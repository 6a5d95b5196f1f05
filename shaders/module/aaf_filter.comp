#version 460
// Axis-aligned filtering, pass 3 (Mehta et al. 2013 §5): a separable
// screen-space Gaussian whose σ is the centre pixel's world-space β, weighted
// by world distance, rejecting neighbours whose normals differ by more than
// the limit angle, and neighbours without a β of their own (another receiver
// class: the glossy term is filtered only among glossy receivers).
// Rows: input → temp (β carried in temp.a); columns: temp → output. The
// columns pass reads β only from temp, so output may be the input image.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"
#include "shared/aaf.h"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { AafFilterPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = filterSize();
  if (any(greaterThanEqual(p, size))) return;
  vec4 centre = imageLoad(filterPosition, p);
  vec4 source = pc.vertical == 0u ? imageLoad(filterInput, p) : imageLoad(filterTemp, p);
  vec3 result = source.rgb;
  // β in the position image's units, as the distances below: the params hold metres, and the row pass
  // hands the converted value on in the temporary image's alpha (which may be half floats).
  const float width = pc.vertical == 0u ? imageLoad(filterParams, p).w / pc.positionScale : source.w;
  if (centre.w > 0.0 && width > 0.0) {
    vec3 n = imageLoad(filterGuidance, p).xyz * 2.0 - 1.0;
    float pixel = centre.w * pc.pixelScale;
    // 3σ in pixels of frontal size: along a foreshortened surface a pixel spans more, so this reaches at least 3σ.
    float limit = float(pc.maxRadius > 0u ? pc.maxRadius : uint(max(size.x, size.y)));
    int radius = int(min(ceil(3.0 * width / max(pixel, 1e-30)), limit));
    ivec2 axis = pc.vertical == 0u ? ivec2(1, 0) : ivec2(0, 1);
    float inv = 0.5 / (width * width);
    vec3 sum = vec3(0.0);
    float weightSum = 0.0;
    for (int k = -radius; k <= radius; ++k) {
      ivec2 q = p + axis * k;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      vec4 x = imageLoad(filterPosition, q);
      if (x.w <= 0.0) continue;
      vec4 v = pc.vertical == 0u ? imageLoad(filterInput, q) : imageLoad(filterTemp, q);
      if ((pc.vertical == 0u ? imageLoad(filterParams, q).w : v.w) <= 0.0) continue;
      vec3 nq = imageLoad(filterGuidance, q).xyz * 2.0 - 1.0;
      if (dot(n, nq) < pc.cosNormalLimit * length(n) * length(nq)) continue;
      vec3 d = x.xyz - centre.xyz;
      float w = exp(-dot(d, d) * inv);
      sum += w * v.rgb;
      weightSum += w;
    }
    result = weightSum > 0.0 ? sum / weightSum : source.rgb;
  }
  if (pc.vertical == 0u) imageStore(filterTemp, p, vec4(result, width));
  else filterStoreOutput(p, result, pc.encoding);
}
