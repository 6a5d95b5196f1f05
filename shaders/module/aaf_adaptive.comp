#version 460
// Axis-aligned filtering, pass 2: the remaining n − 16 samples per pixel,
// stratified over the hemisphere like pass 1's (aafStratum: each sample in a
// cell of its own), scaled down uniformly when the frame's sample budget is
// smaller than what pass 1 asked for. Writes the noisy demodulated indirect (the filter's
// input) and, on glossy receivers, the mean specular terms (filtered in place).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "aaf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

// Sample i of n: in a stratum of its own (aafStratum), then the lobe choice.
vec3 aafSampleU(uint i, uint n, uint offset, GiBsdf b, inout GiRng rng) {
  float cell;
  vec2 u = aafStratum(i, n, offset, cell) + giRandom2(rng) * cell;
  return vec3(u, aafLobeChoice(b, rng));
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = giInFrame(gl_GlobalInvocationID.xy);
  uint traced = 0u;
  if (inside) {
    vec4 params = imageLoad(giAafParams, p);
    vec4 sum = aafLoadPartial(p);
    vec4 glossy = vec4(0.0), edge = vec4(0.0);
    if (pc.glossy != 0u) {
      glossy = imageLoad(giAafGlossy, p);
      edge = imageLoad(giAafGlossyEdge, p);
    }
    if (sum.a > 0.0) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex, pc.seed ^ 0x68bc21ebu, GI_STREAM_AAF);
      float extra = max(params.z - float(AAF_INITIAL_SAMPLES), 0.0);
      if (pc.sampleBudget > 0u) {
        float initial = float(giCounters.coveredPixels) * float(AAF_INITIAL_SAMPLES);  // pass 1's, already spent
        float wanted = max(float(giCounters.requestedSamples) - initial, 1.0);
        float scale = clamp((float(pc.sampleBudget) - initial) / wanted, 0.0, 1.0);
        extra = floor(extra * scale + giRandom(rng));  // unbiased rounding of the scaled count
      }
      uint offset = uint(giRandom(rng) * 4294967040.0);
      GiTask t = aafTaskStart(s, V, rng, false, uint(extra), offset);
      t.diffuse = sum.rgb;  // the sums go on from pass 1's
      t.specular = glossy.rgb;
      t.specularEdge = edge.rgb;
      giRunTask(t);
      sum.rgb = t.diffuse;
      glossy.rgb = t.specular;
      edge.rgb = t.specularEdge;
      sum.a += float(uint(extra));
      params.z = sum.a;
      traced = uint(sum.a);
      imageStore(giAafParams, p, params);
    }
    float inv = sum.a > 0.0 ? 1.0 / sum.a : 0.0;
    vec3 indirect = sum.rgb * inv;
    giStoreNoisy(p, indirect, 1.0);
    giStoreIndirect(p, indirect);
    if (pc.glossy != 0u) {
      imageStore(giAafGlossy, p, vec4(glossy.rgb * inv, glossy.a));
      imageStore(giAafGlossyEdge, p, vec4(edge.rgb * inv, edge.a));
    }
  }
  uint total = subgroupAdd(traced);
  if (subgroupElect()) atomicAdd(giCounters.tracedSamples, total);
  giCountRays(inside);
}
