#version 460
// Hashed path space filtering, deferred claims (HpsfSettings::deferredClaims):
// after the frame's inserts, before resolve, each free slot that keys asked
// for becomes the cell of the largest of them (hgInsertOrFind says why).
// Resolve then keeps the new cells (seen this frame), and their first
// samples come with the next frame's inserts.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  const uint claimed = i < pc.capacity && hgClaimAsked(pc.table, i, pc.frameIndex) ? 1u : 0u;
  const uint sum = subgroupAdd(claimed);
  if (subgroupElect() && sum > 0u) atomicAdd(hgTelemetry.claimed, sum);
}
