#version 460
// Guided filtering's supersampling (Bauszat et al. 2011, §3.2): extra eye
// rays per pixel get their own direct light, and take their indirect light
// from the filtered map at whichever of the four surrounding guide rays is
// most similar in normal and depth (eqs. 3–5). A box filter combines them
// with the guide ray's own result.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "lights.glsl"
#include "gi_frame.glsl"
#include "shared/gi_filters.h"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiSupersamplePush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  if (inside) {
    ivec2 size = ivec2(giFrame.size);
    vec3 sum = giLoadComposite(p);  // the guide ray's own sample
    for (uint k = 0u; k < pc.supersamples; ++k) {
      GiRng rng = giRngCreate(uvec2(p), giFrame.frameIndex * pc.supersamples + k, pc.seed, GI_STREAM_SUPERSAMPLE);
      vec2 pos = vec2(p) + giRandom2(rng);
      vec3 dir = giCameraRayDirection(giFrame.camera, pos);
      GiHit hit = giTraceClosest(giFrame.camera.position, dir, 0.0, GI_FLT_MAX);
      if (hit.t < 0.0) {  // the background
        sum += giSkyRadiance(dir);
        continue;
      }
      GiSurface s = giSurfaceFromHit(hit, dir);
      GiBsdf b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
      vec3 direct = s.material.emission + giDirectLight(s, b, -dir, false, rng);
      float depth = giViewDepth(giFrame.camera, s.position);
      // The four guide rays around the sample, and the most similar one (eqs. 3–5).
      ivec2 base = ivec2(floor(pos - 0.5));
      ivec2 guides[4] = ivec2[4](base, base + ivec2(1, 0), base + ivec2(0, 1), base + ivec2(1, 1));
      vec4 dn, dd;
      for (int i = 0; i < 4; ++i) {
        guides[i] = clamp(guides[i], ivec2(0), size - 1);
        bool covered = giGbCovered(guides[i]);
        vec3 n = covered ? giGbNormal(guides[i]) : -s.normal;
        float z = covered ? giGbViewDepth(guides[i]) : 0.0;
        dn[i] = length(s.normal - n);
        dd[i] = abs(depth - z);
      }
      int best = gifMostSimilarGuide(dn, dd);
      vec3 indirect = max(giLoadIndirect(guides[best]), vec3(0.0));
      sum += direct + b.diffuse * indirect;
    }
    giStoreComposite(p, sum / float(pc.supersamples + 1u));
  }
  giCountRays(inside);
}
