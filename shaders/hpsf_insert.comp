#version 460
// Hashed path space filtering, insert (Meijer 2019 Alg. 1–4): per pixel, N
// paths from the primary hit, which is the filter vertex when its material
// has a diffuse lobe (giHasDiffuseLobe). The demodulated indirect radiance
// arriving there (throughput reset at the vertex; albedo never multiplied
// in) goes into the cell of the vertex's jittered, quantised position. Direct
// light stays per pixel. A pure metal has no diffuse lobe: the composite
// gives its diffuse indirect light no weight, so it is not filtered.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf_walk.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      float kept = 0.0;
      for (uint i = 0u; i < pc.samplesPerPixel; ++i) {
        GiRng rng = giRngCreate(uvec2(p), pc.frameIndex * pc.samplesPerPixel + i, pc.seed, GI_STREAM_MODULE);
        GiPathSample path = giTracePathFromSurface(s, V, pc.maxBounces, pc.russianRouletteStart, rng);
        if (!giKeepSample(path.direct, path.indirectDemod)) continue;
        kept += 1.0;
        direct += path.direct;
        indirect += path.indirectDemod;
      }
      float inv = 1.0 / max(kept, 1.0);
      direct = s.material.emission + direct * inv;
      indirect *= inv;
      filterVertex = giHasDiffuseLobe(s.material);
      if (filterVertex) {
        GiRng rng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
        HgDescriptor d = hgPrimaryDescriptor(s.position, s.normal, rng);
        vec3 probeOrigin = giOffsetRay(s.position, s.geometricNormal);
        vec3 probeDirection = giCosineSample(s.normal, giRandom2(rng));
        // The lookup finds this cell again from the same surface and random numbers (hgPixelCell).
        hgInsertSample(hgIndexHash(d), hgVerificationKey(d), indirect, 1u, d.lod, probeOrigin, probeDirection);
      }
    }
    giStoreDirect(p, direct);
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  hgFlushTelemetry();
  giCountRays(inside);
}
