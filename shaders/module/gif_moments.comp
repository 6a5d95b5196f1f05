#version 460
// Guided filter, step 1: per-pixel products whose window means give the
// guidance covariance and the guidance/input cross-covariance. Background
// pixels (no view depth) carry weight 0 and enter no window: their guidance
// is made up (grey normal, zero depth), and with 1-D guidance a grey normal is
// indistinguishable from real geometry, which would bleed the background's
// black into silhouettes. Channel GIF_CH_WEIGHT holds the weight, so the
// window means become means over the window's covered pixels.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GuidedMomentsPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, filterSize()))) return;
  float w = imageLoad(filterPosition, p).w > 0.0 ? 1.0 : 0.0;
  vec4 I = gifGuidance(p, pc.guidanceDimensions) * w;
  vec3 q = imageLoad(filterInput, p).rgb * w;
  float m[32];
  for (int i = 0; i < 32; ++i) m[i] = 0.0;
  for (int i = 0; i < 4; ++i) m[GIF_CH_I + i] = I[i];
  int k = GIF_CH_II;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j) m[k++] = I[i] * I[j];  // w² = w
  for (int c = 0; c < 3; ++c) m[GIF_CH_P + c] = q[c];
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) m[GIF_CH_IP + 3 * i + c] = I[i] * q[c];
  m[GIF_CH_WEIGHT] = w;
  for (uint img = 0u; img < GIF_MOMENT_IMAGES; ++img)
    imageStore(filterA[img], p, vec4(m[4 * img], m[4 * img + 1], m[4 * img + 2], m[4 * img + 3]));
}
