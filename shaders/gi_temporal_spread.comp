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
  vec2 sum = vec2(0.0), squares = vec2(0.0);  // direct, indirect
  float count = 0.0;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const ivec2 q = p + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(giFrame.size))) || !giGbCovered(q)) continue;
      vec3 direct, indirect;
      giNewFrameLight(q, direct, indirect);
      const vec2 l = vec2(giLuminance(direct), giLuminance(indirect));
      sum += l;
      squares += l * l;
      count += 1.0;
    }
  const GiLuminanceSpread direct = giSpread(sum.x, squares.x, count), indirect = giSpread(sum.y, squares.y, count);
  imageStore(giTemporalSpread, p, vec4(direct.mean, direct.sigma, indirect.mean, indirect.sigma));
}
