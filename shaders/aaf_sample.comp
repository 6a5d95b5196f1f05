#version 460
// Axis-aligned filtering, pass 1 (Mehta et al. 2013 §5): 16 stratified
// cosine rays per pixel give z_min and z_max and the first 16 radiance
// samples; direct light is computed here too. From them: the filter's world
// σ β (eqs. 15–16) and the sample count n (eq. 21), clamped as in the paper.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "aaf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  uint requested = 0u;
  if (inside) {
    vec4 params = vec4(0.0), sum = vec4(0.0);
    vec3 direct = vec3(0.0);
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex, pc.seed, GI_STREAM_AAF);
      GiBsdf b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
      direct = s.material.emission;
      if (pc.ambientOcclusion == 0u) direct += giDirectLight(s, b, V, false, rng);
      float zMin = GI_FLT_MAX, zMax = 0.0;
      for (uint i = 0u; i < AAF_INITIAL_SAMPLES; ++i) {
        vec2 u = (vec2(float(i % 4u), float(i / 4u)) + giRandom2(rng)) * 0.25;  // 4×4 strata
        float t;
        sum.rgb += aafSample(s, u, rng, t);
        if (t >= 0.0) {
          zMin = min(zMin, t);
          zMax = max(zMax, t);
        }
      }
      sum.a = float(AAF_INITIAL_SAMPLES);
      // No reflector seen: treat it as ten scene extents away.
      if (zMax == 0.0) zMin = zMax = 10.0 * pc.sceneExtent;
      zMin = aafClampZMin(zMin, pc.sceneExtent);
      zMax = max(zMax, zMin);
      float d = imageLoad(giGbViewZ, p).r * 2.0 * giFrame.camera.tanHalfFovY / giFrame.camera.imageSize.y;
      float n = pc.uniformSamples > 0u ? float(pc.uniformSamples)
                                       : aafSamples(pc.mu, AAF_OMEGA_DIFFUSE, AAF_GAMMA_DIFFUSE, zMin, zMax, pc.alpha, d);
      params = vec4(zMin, zMax, n, aafBeta(pc.mu, AAF_OMEGA_DIFFUSE, zMin, pc.alpha, d));
      requested = uint(n);
    }
    imageStore(giOutDirect, p, vec4(direct, 1.0));
    imageStore(giAafParams, p, params);
    imageStore(giAafSum, p, sum);
  }
  uint total = subgroupAdd(requested);
  if (subgroupElect()) atomicAdd(giCounters.requestedSamples, total);
  giCountRays(inside);
}
