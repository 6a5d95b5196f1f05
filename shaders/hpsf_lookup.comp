#version 460
// Hashed path space filtering, lookup (Meijer Alg. 5): each pixel reads the
// resolved mean of its own cell, or keeps its own sample when the cell is
// missing or holds too few samples.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "gi_frame.glsl"
#include "hpsf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { HgPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(gl_GlobalInvocationID.xy, giFrame.size))) return;
  vec3 result = imageLoad(giNoisyIndirect, p).rgb;
  uint cell = imageLoad(hgPixelCell, p).r;
  vec4 debug = vec4(0.0);
  if (cell > 0u) {
    HgCell c = hgCells[cell - 1u];
    if (c.samples >= pc.minSamples) result = c.mean;
    uint key = hgKeys[cell - 1u];
    // Debug: cell colour from its key, LOD, samples, and whether the cell was used.
    debug = vec4(float(key & 0xffffffu), float(c.lod), float(c.samples), c.samples >= pc.minSamples ? 1.0 : 0.5);
  }
  imageStore(giOutIndirect, p, vec4(result, 1.0));
  imageStore(giDebug, p, debug);
}
