#version 460
// Axis-aligned filtering, pass 1 (Mehta et al. 2013 §5): 16 stratified
// rays per pixel give z_min and z_max and the first 16 radiance samples;
// direct light is computed here too. From them: the filter's world σ β
// (eqs. 15–16) and the sample count n (eq. 21), clamped as in the paper.
// Glossy receivers also get β for their specular lobe's band limit (eq. 18
// with the Blinn-Phong exponent of their GGX lobe), and n covers both lobes.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "aaf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

// Sample i of the 16: stratified 4×4, then the lobe choice.
vec3 aafSampleU(uint i, uint n, uint offset, GiBsdf b, inout GiRng rng) {
  vec2 stratum = (vec2(float(i % 4u), float(i / 4u)) + giRandom2(rng)) * 0.25;
  return vec3(stratum, aafLobeChoice(b, rng));
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  uint requested = 0u, covered = 0u;
  if (inside) {
    vec4 params = vec4(0.0), sum = vec4(0.0), glossy = vec4(0.0), edge = vec4(0.0);
    vec3 direct = vec3(0.0);
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex, pc.seed, GI_STREAM_AAF);
      GiTask t = aafTaskStart(s, V, rng, pc.ambientOcclusion == 0u, AAF_INITIAL_SAMPLES, 0u);
      t.reservoir = giPrimaryReservoir(p);
      giRunTask(t);
      GiBsdf b = t.b;
      direct = s.material.emission + t.direct;
      sum.rgb = t.diffuse;
      glossy.rgb = t.specular;
      edge.rgb = t.specularEdge;
      float zMin = t.zMin, zMax = t.zMax;
      sum.a = float(AAF_INITIAL_SAMPLES);
      // No reflector seen: treat it as ten scene extents away.
      if (zMax == 0.0) zMin = zMax = 10.0 * pc.sceneExtent;
      zMin = aafClampZMin(zMin, pc.sceneExtent);
      zMax = max(zMax, zMin);
      float d = aafPixelFootprint(giGbViewDepth(p), 2.0 * giFrame.camera.tanHalfFovY / giFrame.camera.imageSize.y,
                                  dot(s.normal, V));
      float n = pc.uniformSamples > 0u ? float(pc.uniformSamples)
                                       : aafSamples(pc.mu, AAF_OMEGA_DIFFUSE, AAF_GAMMA_DIFFUSE, zMin, zMax, pc.alpha, d);
      if (aafGlossyReceiver(b)) {
        float m = aafPhongExponent(b.alpha);
        float omega = aafOmegaGlossy(m);
        if (pc.uniformSamples == 0u) n = max(n, aafSamples(pc.mu, omega, aafGammaGlossy(m), zMin, zMax, pc.alpha, d));
        glossy.a = edge.a = aafBeta(pc.mu, omega, zMin, pc.alpha, d);
      }
      params = vec4(zMin, zMax, n, aafBeta(pc.mu, AAF_OMEGA_DIFFUSE, zMin, pc.alpha, d));
      requested = uint(n);
      covered = 1u;
    }
    giStoreDirect(p, direct);
    imageStore(giAafParams, p, params);
    aafStorePartial(p, sum.rgb, sum.a);
    if (pc.glossy != 0u) {
      imageStore(giAafGlossy, p, glossy);
      imageStore(giAafGlossyEdge, p, edge);
    }
  }
  uint total = subgroupAdd(requested), coveredTotal = subgroupAdd(covered);
  if (subgroupElect()) {
    atomicAdd(giCounters.requestedSamples, total);
    atomicAdd(giCounters.coveredPixels, coveredTotal);
  }
  giCountRays(inside);
}
