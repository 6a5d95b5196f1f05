#version 460
// Test workload for the hash map (tests/hash_grid_test.cpp), through the same
// functions the hpsf passes use:
//  HG_STRESS_INSERT: thread i adds `count` samples of (1, 2, 0.5) to key
//    (keyBase + i mod keyCount): count 1 inserts, count 0 only finds (as a
//    continued path's extra light does);
//  HG_STRESS_EVICT: thread i evicts key keyBase + i (as resolve does);
//  HG_STRESS_TIDY: thread i tidies slot i (as resolve does for tombstones);
//  HG_STRESS_CLAIM: thread i gives slot i to the key that asked for it (deferred claims).
// With sameIndex = 1 every key starts probing at slot 0: one long chain.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"
#include "shared/hash_stress.h"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgStressPush pc; };

HgDescriptor stressKey(uint k) {
  HgDescriptor d;
  d.x = int(k);
  d.y = 1;
  d.z = -1;
  d.lod = 0;
  d.normalBits = 0u;
  return d;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (pc.mode == HG_STRESS_TIDY) {
    if (i < pc.capacity) hgTidyTombstone(0u, i, pc.capacity);
    return;
  }
  if (pc.mode == HG_STRESS_CLAIM) {
    if (i < pc.capacity) hgClaimAsked(0u, i, 0u);
    return;
  }
  if (i >= pc.keyCount * (pc.mode == HG_STRESS_INSERT ? pc.repeats : 1u)) return;
  HgDescriptor d = stressKey(pc.keyBase + i % pc.keyCount);
  uint index = pc.sameIndex != 0u ? 0u : hgIndexHash(d);
  if (pc.mode == HG_STRESS_EVICT) {
    int slot = hgFind(0u, index, hgVerificationKey(d), pc.capacity, pc.window);
    if (slot >= 0) hgEvict(0u, uint(slot), pc.capacity);
    return;
  }
  uint probes;
  bool created;
  int slot = hgInsertOrFind(0u, index, hgVerificationKey(d), pc.capacity, pc.window, pc.count > 0u, pc.deferred != 0u, 0u,
                            probes, created);
  if (slot == HG_SLOT_ASKED) return;
  if (slot < 0) {
    atomicAdd(hgTelemetry.failedInserts, 1u);
    return;
  }
  bool overflowed = false;
  hgAccumulate(slot, vec3(1.0, 2.0, 0.5), vec3(0.0), 1.0, pc.count, overflowed);
  atomicMax(hgTelemetry.probeMax, probes);
}
