#version 460
// Test workload for the hash map: thread i inserts key (i mod keyCount) and
// adds 1 to its cell, so every present key must end with count = repeats.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { uint capacity; uint window; uint keyCount; uint repeats; } pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.keyCount * pc.repeats) return;
  HgDescriptor d;
  d.x = int(i % pc.keyCount);
  d.y = 1;
  d.z = -1;
  d.lod = 0;
  d.normalBits = 0u;
  uint probes;
  bool created;
  int slot = hgInsertOrFind(0u, hgIndexHash(d), hgVerificationKey(d), pc.capacity, pc.window, probes, created);
  if (slot < 0) {
    atomicAdd(hgTelemetry.failedInserts, 1u);
    return;
  }
  bool overflowed = false;
  hgAccumulate(slot, vec3(1.0, 2.0, 0.5), 1.0, 1u, overflowed);
  atomicMax(hgTelemetry.probeMax, probes);
}
