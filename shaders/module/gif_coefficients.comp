#version 460
// Guided filter, step 2: per window, a = (Σ + εU)⁻¹ · cov(I, p) and
// b = mean(p) − aᵀ · mean(I) (He et al. 2010; Bauszat et al. 2011 eq. 2),
// the means over the window's covered pixels (gif_moments.comp). The
// coefficients are written times the window's covered fraction w̄, so that a
// window mostly over background counts little when gif_output averages them,
// and one with no covered pixel not at all.
// Σ + εU is symmetric positive definite, solved by Cholesky. Written in
// place over the window means (each thread reads and writes its own
// statistics pixel, 1/s of the render rectangle).
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_GROUP_SIZE, local_size_y = FILTER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GuidedCoefficientsPush pc; };

// ε below this would leave Σ singular on flat guidance (every variance 0).
#define GIF_MIN_EPSILON 1e-7

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, gifStackSize(pc.subsample)))) return;
  float m[32];
  for (uint img = 0u; img < GIF_MOMENT_IMAGES; ++img) {
    vec4 v = imageLoad(filterA[img], p);
    m[4 * img] = v.x;
    m[4 * img + 1] = v.y;
    m[4 * img + 2] = v.z;
    m[4 * img + 3] = v.w;
  }
  float weight = m[GIF_CH_WEIGHT];
  float coeff[16];
  for (int i = 0; i < 16; ++i) coeff[i] = 0.0;
  if (weight < 1e-6) {  // no covered pixel in the window: it contributes nothing
    for (uint img = 0u; img < GIF_COEFF_IMAGES; ++img) imageStore(filterA[img], p, vec4(0.0));
    return;
  }
  for (int i = 0; i < GIF_CH_WEIGHT; ++i) m[i] /= weight;
  float meanI[4], S[4][4];
  for (int i = 0; i < 4; ++i) meanI[i] = m[GIF_CH_I + i];
  int k = GIF_CH_II;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j) {
      float cov = m[k++] - meanI[i] * meanI[j];
      S[i][j] = cov;
      S[j][i] = cov;
    }
  for (int i = 0; i < 4; ++i) S[i][i] += max(i < 3 ? pc.epsilonNormal : pc.epsilonDepth, GIF_MIN_EPSILON);
  // Cholesky: S = L·Lᵀ.
  float L[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) L[i][j] = 0.0;
  for (int j = 0; j < 4; ++j) {
    float d = S[j][j];
    for (int t = 0; t < j; ++t) d -= L[j][t] * L[j][t];
    L[j][j] = sqrt(max(d, 1e-30));
    for (int i = j + 1; i < 4; ++i) {
      float s = S[i][j];
      for (int t = 0; t < j; ++t) s -= L[i][t] * L[j][t];
      L[i][j] = s / L[j][j];
    }
  }
  for (int c = 0; c < 3; ++c) {
    float meanP = m[GIF_CH_P + c];
    float rhs[4], y[4], a[4];
    for (int i = 0; i < 4; ++i) rhs[i] = m[GIF_CH_IP + 3 * i + c] - meanI[i] * meanP;
    for (int i = 0; i < 4; ++i) {  // L·y = rhs
      float s = rhs[i];
      for (int t = 0; t < i; ++t) s -= L[i][t] * y[t];
      y[i] = s / L[i][i];
    }
    for (int i = 3; i >= 0; --i) {  // Lᵀ·a = y
      float s = y[i];
      for (int t = i + 1; t < 4; ++t) s -= L[t][i] * a[t];
      a[i] = s / L[i][i];
    }
    float b = meanP;
    for (int i = 0; i < 4; ++i) {
      coeff[3 * i + c] = a[i];
      b -= a[i] * meanI[i];
    }
    coeff[GIF_COEFF_B + c] = b;
  }
  for (int i = 0; i < GIF_COEFF_WEIGHT; ++i) coeff[i] *= weight;
  coeff[GIF_COEFF_WEIGHT] = weight;
  for (uint img = 0u; img < GIF_COEFF_IMAGES; ++img)
    imageStore(filterA[img], p, vec4(coeff[4 * img], coeff[4 * img + 1], coeff[4 * img + 2], coeff[4 * img + 3]));
}
