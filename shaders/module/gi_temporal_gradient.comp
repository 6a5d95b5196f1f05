#version 460
// Temporal gradients (temporal.glsl), one invocation per tile: the tile's
// gradient pixel this frame traces one more path with the random state its
// reprojected pixel's first path had last frame, and the tile keeps the
// change of the two samples' luminances and the larger of them (direct over
// the base colour, demodulated indirect); zero where the pixel has no source.
// With reservoirs the path shades with last frame's light pick (temporal.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "path_task.glsl"
#include "temporal.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiRawPush pc; };

void main() {
  const ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  const bool inside = all(lessThan(tile, giGradientTiles()));
  bool traced = false;
  if (inside) {
    const ivec2 p = giGradientPixel(tile, giFrame.frameIndex, pc.seed);
    vec4 gradient = vec4(0.0);
    ivec2 q;
    if (giGbCovered(p) && giGradientSource(p, pc.depthTolerance, pc.cosNormalLimit, q)) {
      const uvec4 source = pc.readSet == 0u ? imageLoad(giGradientSamplesA, q) : imageLoad(giGradientSamplesB, q);
      vec3 V;
      const GiSurface s = giGbSurface(p, V);
      GiRng rng;
      rng.state = source.y;
      // With reservoirs, last frame's light pick (the light and W its first path shaded with).
      const uvec2 reservoir = giFrameHasReservoirs() ? source.zw
                              : giFrame.primaryDirect == GI_PRIMARY_DIRECT_NONE     ? GI_NO_NEE
                                                                                    : GI_NO_RESERVOIR;
      const GiPathSample path = giTracePathFromSurface(s, V, pc.maxBounces, pc.russianRouletteStart, reservoir, rng);
      const vec2 now = giKeepSample(path.direct, path.indirectDemod)
                           ? giGradientLuminance(path.direct, path.indirectDemod, p)
                           : vec2(0.0);
      const vec2 then = unpackHalf2x16(source.x);
      const uint packed = giPackGradientLuminance(now);
      const bvec2 same = bvec2((packed & 0xffffu) == (source.x & 0xffffu), (packed >> 16u) == (source.x >> 16u));
      gradient = vec4(same.x ? 0.0 : now.x - then.x, max(now.x, then.x), same.y ? 0.0 : now.y - then.y,
                      max(now.y, then.y));
      traced = true;
    }
    imageStore(giTemporalGradient, tile, gradient);
  }
  giCountRays(traced);
}
