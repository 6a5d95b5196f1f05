#version 460
// Hashed path space filtering, insert (Meijer 2019 Alg. 1–4): per pixel, N
// paths from the primary hit, which is the filter vertex when its material is
// diffuse. The demodulated indirect radiance arriving there (throughput reset
// at the vertex; albedo never multiplied in) goes into the cell of the
// vertex's jittered, quantised position. Direct light stays per pixel.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "path.glsl"
#include "gi_frame.glsl"
#include "hpsf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  uint probes = 0u, failed = 0u, inserted = 0u, overflowCount = 0u;
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    uint cell = 0u;
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
      bool filterVertex = (s.material.flags & MATERIAL_FLAG_GLOSSY) == 0u;  // the first diffuse vertex
      if (filterVertex) {
        GiRng rng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
        float travel = distance(giFrame.camera.position, s.position);
        int lod = hgLod(pc.filterWidth, pc.pixelAngle, travel, pc.stochasticLod != 0u ? giRandom(rng) : 0.0);
        vec3 jittered = s.position + hgJitter(s.normal, giRandom2(rng), pc.jitter, exp2(float(lod)));
        HgDescriptor d = hgDescriptor(jittered, s.normal, lod, pc.normalBits);
        uint index = hgIndexHash(d), key = hgVerificationKey(d);
        int slot = hgInsertOrFind(pc.table, index, key, pc.capacity, pc.probeWindow, probes);
        if (slot < 0) {
          failed = 1u;
        } else {
          // Outliers are clamped against the cell's history (mean + kσ of luminance), so one
          // firefly cannot poison the cache. With strict eviction the history is the same
          // key's cell in the previous frame's table, which this cell links to and keeps alive.
          HgCell history = hgCells[slot];
          if (pc.strict != 0u) {
            int previous = hgFind(pc.previousTable, index, key, pc.capacity, pc.probeWindow);
            if (previous >= 0) {
              history = hgCells[previous];
              hgCells[slot].previous = uint(previous) + 1u;  // every writer of this key writes the same value
              hgCells[previous].lastSeen = pc.frameIndex;
            }
          }
          vec3 sample_ = indirect;
          if (pc.clampSigma > 0.0 && history.samples >= 8u) {
            float mean = dot(history.mean, vec3(0.2126, 0.7152, 0.0722));
            float sigma = sqrt(max(history.lumMoment2 - mean * mean, 0.0));
            float limit = mean + pc.clampSigma * sigma;
            float lum = dot(sample_, vec3(0.2126, 0.7152, 0.0722));
            if (lum > limit && lum > 0.0) sample_ *= limit / lum;
          }
          bool overflowed = false;
          hgAccumulate(slot, sample_, overflowed);
          overflowCount = overflowed ? 1u : 0u;
          hgCells[slot].lod = d.lod;  // every writer of this key writes the same value
          cell = uint(slot) + 1u;
          inserted = 1u;
        }
      }
    }
    imageStore(giOutDirect, p, vec4(direct, 1.0));
    imageStore(giNoisyIndirect, p, vec4(indirect, 1.0));
    imageStore(hgPixelCell, p, uvec4(cell));
  }
  // Telemetry: one atomic per subgroup and counter.
  uint sumInserted = subgroupAdd(inserted), sumFailed = subgroupAdd(failed), sumProbes = subgroupAdd(probes);
  uint maxProbes = subgroupMax(probes), sumOverflow = subgroupAdd(overflowCount);
  if (subgroupElect()) {
    if (sumInserted > 0u) atomicAdd(hgTelemetry.inserts, sumInserted);
    if (sumFailed > 0u) atomicAdd(hgTelemetry.failedInserts, sumFailed);
    if (sumProbes > 0u) atomicAdd(hgTelemetry.probeSum, sumProbes);
    if (maxProbes > 0u) atomicMax(hgTelemetry.probeMax, maxProbes);
    if (sumOverflow > 0u) atomicAdd(hgTelemetry.overflows, sumOverflow);
  }
  giCountRays(inside);
}
