#version 460
// Path space filtering at every diffuse vertex (Meijer 2019 §4.3–4.4).
//  nhpsf:  per pixel and sample, a walk of pathDepth segments from the
//          primary hit; each diffuse vertex's cell gets the radiance that one
//          segment brings it (NEE at the next vertex plus that vertex's
//          albedo × its cell from last frame's map).
//  anhpsf: per pixel and sample, the primary segment; then one segment of the
//          pixel's continued walk (2 rays: the segment and its shadow ray),
//          stored across frames up to continuationDepth segments in all (the
//          primary segment is the first). The deepest live walk continues; a
//          dead or finished one restarts where this frame's primary segment landed. Light found deep down feeds the
//          cells along the walk and reaches the primary cells through the map.
// The primary vertex's walk uses a cosine direction whatever its material:
// the cell (and the pixel's own fallback sample) holds demodulated light. It
// feeds the primary cell when the vertex has a diffuse lobe (giHasDiffuseLobe).
// Direct light takes one NEE sample per path, averaged like the indirect.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf_walk.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(gl_GlobalInvocationID.xy, giFrame.size));
  uint continued = 0u, depthSum = 0u;
  if (inside) {
    vec3 direct = vec3(0.0), indirect = vec3(0.0);
    bool filterVertex = false;
    uint pixel = uint(p.y) * giFrame.size.x + uint(p.x);
    HgWalk stored;
    stored.state = 0u;
    if (pc.mode == HG_MODE_ANHPSF) stored = hgWalks[pixel];
    if (giGbCoveredCounting(p)) {
      vec3 V;
      GiSurface s = giGbSurface(p, V);
      GiRng hashRng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_HASH);
      HgDescriptor d0 = hgPrimaryDescriptor(s.position, s.normal, hashRng);
      filterVertex = giHasDiffuseLobe(s.material);
      GiRng rng = giRngCreate(uvec2(p), pc.frameIndex, pc.seed, GI_STREAM_MODULE);
      GiBsdf b = giMakeBsdf(s.material.baseColor, s.material.metallic, s.material.roughness, s.material.flags);
      HgWalk restart;
      restart.state = 0u;
      for (uint i = 0u; i < pc.samplesPerPixel; ++i) {
        direct += giDirectLight(s, b, V, false, rng);
        HgWalk walk = hgWalkFrom(s, d0, filterVertex, 1u, hgPrimaryTravel(s.position), rng);
        indirect += hgStep(walk, rng);  // the primary segment: the pixel's own sample
        uint segments = pc.mode == HG_MODE_NHPSF ? pc.depth : 1u;
        for (uint k = 1u; k < segments && hgWalkDepth(walk) > 0u; ++k) hgStep(walk, rng);
        if (hgWalkDepth(restart) == 0u) restart = walk;
      }
      direct = s.material.emission + direct / float(pc.samplesPerPixel);
      indirect /= float(pc.samplesPerPixel);
      if (pc.mode == HG_MODE_ANHPSF) {
        // The deepest live walk with segments left continues (a walk that has
        // taken k segments sits at vertex k + 1); otherwise this frame's.
        if (hgWalkDepth(stored) == 0u || hgWalkSegments(stored) >= pc.depth) stored = restart;
        if (hgWalkDepth(stored) > 0u && hgWalkSegments(stored) < pc.depth) hgStep(stored, rng);
        continued = hgWalkDepth(stored) > 0u ? 1u : 0u;
        depthSum = hgWalkSegments(stored);
      }
    } else {
      stored.state = 0u;  // background: nothing to continue
    }
    if (pc.mode == HG_MODE_ANHPSF) hgWalks[pixel] = stored;
    giStoreDirect(p, direct);
    giStoreNoisy(p, indirect, filterVertex ? 1.0 : 0.0);
  }
  uint sumContinued = subgroupAdd(continued), sumDepth = subgroupAdd(depthSum);
  if (subgroupElect() && sumContinued > 0u) {
    atomicAdd(hgTelemetry.continued, sumContinued);
    atomicAdd(hgTelemetry.depthSum, sumDepth);
  }
  hgFlushTelemetry();
  giCountRays(inside);
}
