#version 460
// SVGF's variance estimate (Schied et al. 2017 §4.2): per pixel, the
// luminance variance of the accumulated direct and indirect light from their
// temporally integrated moments, σ² = E[l²] − E[l]²; while a pixel has fewer
// than GI_TRUSTED_HISTORY (4) frames of history, from the moments of its 7×7 neighbourhood
// instead, weighted by depth and normal. Writes the pair of images (light,
// σ²) the first à-trous iteration reads (svgf.glsl), this frame's history
// guide (read by the iterations and next frame's temporal pass), and for the
// svgf variance view the debug image (σ² direct, σ² indirect, frames).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "svgf.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiSvgfPush pc; };


void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  const vec4 direct = pc.writtenSet == 0u ? giLoadHistoryDirectA(p) : giLoadHistoryDirectB(p);
  const vec3 indirect = giLoadHistoryIndirect(pc.writtenSet, p).rgb;
  const float frames = giLoadSvgfFrames(pc.writtenSet, p);
  // This frame's guide, stored for the à-trous iterations and next frame's temporal pass.
  const uint packedGuide = giCurrentGuide(p);
  imageStore(giHistoryGuide, p, uvec4(packedGuide));
  const vec4 guide = giUnpackGuide(packedGuide);
  vec2 variance = vec2(0.0);
  if (guide.w > 0.0 && !giHistoryTrusted(frames)) {
    const vec2 gradient = svgfDepthGradient(p, guide.w, false);
    vec2 mean = vec2(0.0), square = vec2(0.0);
    float weights = 0.0;
    for (int j = -3; j <= 3; ++j)
      for (int i = -3; i <= 3; ++i) {
        const ivec2 q = p + ivec2(i, j);
        const vec4 tap = svgfGuide(q, false);
        if (tap.w <= 0.0) continue;
        const float w = i == 0 && j == 0 ? 1.0 : svgfGeometryWeight(guide, gradient, tap, vec2(i, j), pc.sigmaDepth, pc.sigmaNormal);
        const GiMoments m = giLoadMoments(pc.writtenSet, q);
        mean += w * m.mean;
        square += w * (m.variance + m.mean * m.mean);
        weights += w;
      }
    mean /= weights;
    variance = max(vec2(0.0), square / weights - mean * mean);
  } else if (guide.w > 0.0) {
    variance = giLoadMoments(pc.writtenSet, p).variance;
  }
  if (pc.debug != 0u) imageStore(giDebug, p, vec4(variance, frames, 0.0));
  if (guide.w > 0.0)
    svgfStore(svgfReadPair(0u, pc.iterations), pc.writtenSet, p,
              SvgfTexel(vec4(direct.rgb, variance.x), vec4(indirect, variance.y)), pc.direct);
}
