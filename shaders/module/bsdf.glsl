// The material model: Lambert, plus a GGX lobe only for materials flagged
// MATERIAL_FLAG_GLOSSY. f = (1 − metallic)·baseColor/π + D·Vis·F, with
// F0 = mix(0.04, baseColor, metallic). Directions are unit vectors pointing
// away from the surface; N faces the incoming ray's side.
#ifndef GI_BSDF_GLSL
#define GI_BSDF_GLSL
#include "common.glsl"
#include "shared/gpu_scene.h"

struct GiBsdf {
  vec3 diffuse;               // diffuse albedo
  vec3 f0;                    // specular reflectance at normal incidence (0 without a glossy lobe)
  float alpha;                // GGX alpha = roughness², clamped away from a delta lobe
  float specularProbability;  // chance of sampling the GGX lobe, 0 without one
};

GiBsdf giMakeBsdf(vec3 baseColor, float metallic, float roughness, uint flags) {
  GiBsdf b;
  if ((flags & MATERIAL_FLAG_GLOSSY) != 0u) {
    b.diffuse = (1.0 - metallic) * baseColor;
    b.f0 = mix(vec3(0.04), baseColor, metallic);
    b.alpha = max(roughness * roughness, 2e-3);
    float spec = giLuminance(b.f0), diff = giLuminance(b.diffuse);
    b.specularProbability = clamp(spec / max(spec + diff, 1e-6), 0.1, 0.9);
  } else {
    b.diffuse = baseColor;
    b.f0 = vec3(0.0);
    b.alpha = 1.0;
    b.specularProbability = 0.0;
  }
  return b;
}

float giGgxD(float nh, float a2) {
  float d = nh * nh * (a2 - 1.0) + 1.0;
  return a2 / (GI_PI * d * d);
}

// Height-correlated Smith visibility: G2 / (4 NL NV).
float giGgxVis(float nl, float nv, float a2) {
  float gv = nl * sqrt(nv * nv * (1.0 - a2) + a2);
  float gl = nv * sqrt(nl * nl * (1.0 - a2) + a2);
  return 0.5 / max(gv + gl, 1e-12);
}

// The GGX lobe without its Fresnel factor, D·Vis·cos(N, L), and Schlick's
// weight s = (1 − V·H)^5. With F = f0 + (1 − f0)·s the lobe is
// f0·(1 − s)·lobe + s·lobe: linear in f0, so a filter can keep f0 out of the
// radiance it averages and multiply it back afterwards.
float giSpecularLobe(GiBsdf b, vec3 N, vec3 V, vec3 L, out float schlick) {
  float nl = dot(N, L);
  schlick = 0.0;
  if (nl <= 0.0 || b.specularProbability <= 0.0) return 0.0;
  float nv = max(dot(N, V), 1e-6);
  vec3 H = normalize(V + L);
  float a2 = b.alpha * b.alpha;
  schlick = pow(1.0 - clamp(dot(V, H), 0.0, 1.0), 5.0);
  return giGgxD(max(dot(N, H), 0.0), a2) * giGgxVis(nl, nv, a2) * nl;
}

// f(V, L) · cos(N, L).
vec3 giBsdfEval(GiBsdf b, vec3 N, vec3 V, vec3 L) {
  float nl = dot(N, L);
  if (nl <= 0.0) return vec3(0.0);
  float schlick;
  float lobe = giSpecularLobe(b, N, V, L, schlick);
  return b.diffuse * (GI_INV_PI * nl) + lobe * (b.f0 + (1.0 - b.f0) * schlick);
}

// Solid-angle density of giBsdfSample choosing L.
float giBsdfPdf(GiBsdf b, vec3 N, vec3 V, vec3 L) {
  float nl = dot(N, L);
  if (nl <= 0.0) return 0.0;
  float pdf = (1.0 - b.specularProbability) * nl * GI_INV_PI;
  if (b.specularProbability > 0.0) {
    vec3 H = normalize(V + L);
    float nh = max(dot(N, H), 0.0), vh = max(dot(V, H), 1e-6);
    pdf += b.specularProbability * giGgxD(nh, b.alpha * b.alpha) * nh / (4.0 * vh);
  }
  return pdf;
}

// An orthonormal basis around n (Duff et al. 2017).
void giBasis(vec3 n, out vec3 t, out vec3 bt) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  bt = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 giCosineSample(vec3 n, vec2 u) {
  float r = sqrt(u.x), phi = 2.0 * GI_PI * u.y;
  vec3 t, bt;
  giBasis(n, t, bt);
  return normalize(t * (r * cos(phi)) + bt * (r * sin(phi)) + n * sqrt(max(0.0, 1.0 - u.x)));
}

// A GGX half vector about N for roughness alpha (density D(h)·cos θ_h).
vec3 giGgxHalfVector(vec3 N, float alpha, vec2 u) {
  vec3 t, bt;
  giBasis(N, t, bt);
  float a2 = alpha * alpha;
  float cosTheta = sqrt((1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x));
  float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
  float phi = 2.0 * GI_PI * u.y;
  return t * (sinTheta * cos(phi)) + bt * (sinTheta * sin(phi)) + N * cosTheta;
}

// Samples L; returns false when the sample is below the horizon.
// `weight` = f·cos/pdf, `pdf` = solid-angle density (for MIS).
bool giBsdfSample(GiBsdf b, vec3 N, vec3 V, vec3 u, out vec3 L, out vec3 weight, out float pdf) {
  if (u.z < b.specularProbability) {
    L = reflect(-V, giGgxHalfVector(N, b.alpha, u.xy));
  } else {
    L = giCosineSample(N, u.xy);
  }
  pdf = giBsdfPdf(b, N, V, L);
  if (pdf <= 0.0) {
    weight = vec3(0.0);
    return false;
  }
  weight = giBsdfEval(b, N, V, L) / pdf;
  return true;
}

// Samples L from the GGX lobe alone (no diffuse part); `weight` = the lobe's
// f·cos / its own density. False below the horizon or without a glossy lobe.
bool giSpecularSample(GiBsdf b, vec3 N, vec3 V, vec2 u, out vec3 L, out vec3 weight) {
  weight = vec3(0.0);
  L = N;
  if (b.specularProbability <= 0.0) return false;
  float a2 = b.alpha * b.alpha;
  vec3 H = giGgxHalfVector(N, b.alpha, u);
  L = reflect(-V, H);
  float nh = max(dot(N, H), 0.0), vh = max(dot(V, H), 1e-6);
  float pdf = giGgxD(nh, a2) * nh / (4.0 * vh);
  if (dot(N, L) <= 0.0 || pdf <= 0.0) return false;
  float schlick;
  float lobe = giSpecularLobe(b, N, V, L, schlick);
  weight = lobe * (b.f0 + (1.0 - b.f0) * schlick) / pdf;
  return true;
}

float giPowerHeuristic(float a, float b) {
  float a2 = a * a;
  return a2 / max(a2 + b * b, 1e-30);
}

#endif
