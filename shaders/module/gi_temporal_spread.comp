#version 460
// The history clamp's yardstick (TemporalSettings::historyClamp): the
// luminance mean and standard deviation of this frame's samples over the 3×3
// pixels around each pixel (surfaces only), of the direct light over the base
// colour and of the demodulated indirect, as the temporal pass blends them.
// A pass of its own: the temporal pass replaces those samples in place, so it
// cannot read its neighbours' without a race.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  GiLuminanceSpread direct, indirect;
  giNeighbourhoodSpread(p, GI_SPREAD_NEW_FRAME, 0u, direct, indirect);
  imageStore(giTemporalSpread, p, vec4(direct.mean, direct.sigma, indirect.mean, indirect.sigma));
}
