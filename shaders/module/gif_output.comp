#version 460
// Guided filter, step 3: q = mean(a)ᵀ · I + mean(b), with the coefficients of
// every window that covers the pixel averaged by the box passes, each window
// weighted by its covered fraction (gif_coefficients.comp), and I the pixel's
// own guidance. With statistics at 1/s resolution the mean coefficients are
// interpolated bilinearly between the four statistics pixels around the
// pixel's centre (He & Sun 2015); with s = 1 they are the pixel's own.
// Background pixels keep their input.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GuidedMomentsPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, filterSize()))) return;
  vec4 I = gifGuidance(p, pc.guidanceDimensions);
  const vec2 at = (vec2(p) + 0.5) / float(pc.subsample) - 0.5;  // in statistics pixels
  const ivec2 last = gifStackSize(pc.subsample) - 1;
  const ivec2 c0 = clamp(ivec2(floor(at)), ivec2(0), last), c1 = min(c0 + 1, last);
  const vec2 f = clamp(at - vec2(c0), 0.0, 1.0);
  float coeff[16];
  for (uint img = 0u; img < GIF_COEFF_IMAGES; ++img) {
    vec4 v = pc.subsample == 1u
                 ? imageLoad(filterA[img], p)
                 : mix(mix(imageLoad(filterA[img], c0), imageLoad(filterA[img], ivec2(c1.x, c0.y)), f.x),
                       mix(imageLoad(filterA[img], ivec2(c0.x, c1.y)), imageLoad(filterA[img], c1), f.x), f.y);
    coeff[4 * img] = v.x;
    coeff[4 * img + 1] = v.y;
    coeff[4 * img + 2] = v.z;
    coeff[4 * img + 3] = v.w;
  }
  float weight = coeff[GIF_COEFF_WEIGHT];
  bool covered = imageLoad(filterGuidance, p).w > 0.0 && weight > 0.0;
  for (int i = 0; i < GIF_COEFF_WEIGHT; ++i) coeff[i] = covered ? coeff[i] / weight : 0.0;
  vec3 q = imageLoad(filterInput, p).rgb;
  if (covered) {
    for (int c = 0; c < 3; ++c) {
      float v = coeff[GIF_COEFF_B + c];
      for (int i = 0; i < 4; ++i) v += coeff[3 * i + c] * I[i];
      q[c] = v;
    }
  }
  filterStoreOutput(p, q, pc.encoding);
  if (pc.writeCoefficientView != 0u) {
    float a2 = 0.0;
    for (int i = 0; i < 12; ++i) a2 += coeff[i] * coeff[i];
    vec3 b = vec3(coeff[GIF_COEFF_B], coeff[GIF_COEFF_B + 1], coeff[GIF_COEFF_B + 2]);
    imageStore(filterTemp, p, vec4(sqrt(a2), length(b), 0.0, 1.0));
  }
}
