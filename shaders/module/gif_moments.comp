#version 460
// Guided filter, step 1: per-pixel products whose window means give the
// guidance covariance and the guidance/input cross-covariance, averaged over
// each s×s block of pixels into one statistics pixel (gif.subsample: He & Sun
// 2015's fast guided filter, whose windows and coefficients live at 1/s
// resolution; s = 1 is the full-resolution filter). Background pixels (no view
// depth) carry weight 0 and enter no window: their guidance is made up (grey
// normal, zero depth), and with 1-D guidance a grey normal is
// indistinguishable from real geometry, which would bleed the background's
// black into silhouettes. Channel GIF_CH_WEIGHT holds the weight, so the
// window means become means over the window's covered pixels (a block's mean
// keeps the ratio of its sums).
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GuidedMomentsPush pc; };

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(cell, gifStackSize(pc.subsample)))) return;
  const int s = int(pc.subsample);
  float m[32];
  for (int i = 0; i < 32; ++i) m[i] = 0.0;
  int pixels = 0;
  for (int by = 0; by < s; ++by)
    for (int bx = 0; bx < s; ++bx) {
      ivec2 p = cell * s + ivec2(bx, by);
      if (any(greaterThanEqual(p, filterSize()))) continue;
      ++pixels;
      float w = imageLoad(filterGuidance, p).w > 0.0 ? 1.0 : 0.0;
      vec4 I = gifGuidance(p, pc.guidanceDimensions) * w;
      vec3 q = imageLoad(filterInput, p).rgb * w;
      for (int i = 0; i < 4; ++i) m[GIF_CH_I + i] += I[i];
      int k = GIF_CH_II;
      for (int i = 0; i < 4; ++i)
        for (int j = i; j < 4; ++j) m[k++] += I[i] * I[j];  // w² = w
      for (int c = 0; c < 3; ++c) m[GIF_CH_P + c] += q[c];
      for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) m[GIF_CH_IP + 3 * i + c] += I[i] * q[c];
      m[GIF_CH_WEIGHT] += w;
    }
  const float toMean = 1.0 / float(pixels);  // ≥ 1: the block's first pixel lies in the rectangle
  for (uint img = 0u; img < GIF_MOMENT_IMAGES; ++img)
    imageStore(filterA[img], cell,
               vec4(m[4 * img], m[4 * img + 1], m[4 * img + 2], m[4 * img + 3]) * toMean);
}
