// LIGHT_SAMPLER_TREE's nodes and the importance a path vertex picks a child by, shared by the tree's
// build (gi_module/src/scene/scene_tables.cpp) and lights.glsl, so the CPU tests check the shaders'
// rule: it never rules out a light that can light the surface (light_table_test.cpp). The bounds follow
// Conty Estevez & Kulla 2018 (a sphere round the lights' positions and a cone round the directions they
// aim at); units: metres, the sampling power of scene_tables.cpp's samplingPower.
#ifndef GI_LIGHT_TREE_H
#define GI_LIGHT_TREE_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

// A node of the binary tree over the point and spot lights, stored after the light table in the same
// buffer (node i at byte 64·punctualLightCount + 48·i; the root is node 0, and there are 2n − 1 nodes
// for n lights). After the nodes, the cut: lightCutSize node indices (uint) whose subtrees hold every
// light once. A vertex takes one light from each, walking down from the cut's node and choosing a child
// by lightNodeImportance.
struct GpuLightNode {
  vec3 centre;       // world, metres: a sphere holding the positions of the lights below
  float radius;      // metres: 0 for a leaf
  vec3 axis;         // world, unit: a cone holding every direction the lights below send light in
  float cosAim;      // cos of that cone's half-angle, [−1, 1]: −1 when a point light is below (every
                     // direction); a spot's outer cone angle, widened by kLightConeMargin
  float power;       // Σ of their sampling powers
  uint child;        // LIGHT_NODE_LEAF | the light's index; otherwise the first of two adjacent children
  float cosFalloff;  // cos of how far past the aim cone light still leaves, weighed by the cosine of that
                     // angle (a cosine emitter's π/2: 0); 1 when none does (point and spot lights)
  uint parent;       // the node whose child this is (the root's: 0): a leaf's chance is walked up from it
};
GPU_ASSERT_SIZE(GpuLightNode, 48);
GPU_CONST LIGHT_NODE_LEAF = 0x80000000u;
// LIGHT_SAMPLER_TREE walks the emissive triangles' tree only with more triangles than this: one quad lamp's
// two are picked as well by power, and the walk and the search a BSDF-sampled hit needs for MIS only cost
// time there; four panels' eight gain (docs/RESULTS.md, "Many emissive triangles" and "today's scenes").
GPU_CONST LIGHT_EMISSIVE_TREE_MIN = 2u;

// How much a node's lights may bring to a surface at x (world, metres) with geometric normal ng: their
// power over the squared distance to the sphere's centre, times the cosine of the smallest angle between
// ng and a direction into the sphere (the surface's side), times the cosine of the smallest angle by
// which x lies outside the aim cone seen through the sphere (0 past cosFalloff: no light reaches x).
// 0 means none of the lights can light x, as giPreparePunctual decides; x inside the sphere: any
// direction, power over the radius².
GPU_FN float lightNodeImportance(GpuLightNode n, vec3 x, vec3 ng) {
  const vec3 d = n.centre - x;  // towards the lights
  const float dist2 = dot(d, d), radius2 = n.radius * n.radius;
  if (dist2 <= radius2) return n.power / max(radius2, 1e-30f);
  const float dist = sqrt(dist2);
  const float sinU = n.radius / dist, cosU = sqrt(max(0.0f, 1.0f - sinU * sinU));  // the sphere's half-angle θu
  // The surface's side: cos(θn − θu), θn between ng and the centre.
  const float cosN = dot(ng, d) / dist, sinN = sqrt(max(0.0f, 1.0f - cosN * cosN));
  const float cosSurface = cosN >= cosU ? 1.0f : cosN * cosU + sinN * sinU;
  if (cosSurface <= 0.0f) return 0.0f;
  // The lights' aim: θw between the axis and the direction from the centre to x, less the cone's
  // half-angle θo, less θu (each at least 0).
  const float cosW = -dot(n.axis, d) / dist, sinW = sqrt(max(0.0f, 1.0f - cosW * cosW));
  const float sinAim = sqrt(max(0.0f, 1.0f - n.cosAim * n.cosAim));
  const float cosOutside = cosW >= n.cosAim ? 1.0f : cosW * n.cosAim + sinW * sinAim;  // cos(θw − θo)
  const float sinOutside = sqrt(max(0.0f, 1.0f - cosOutside * cosOutside));
  const float cosPast = cosOutside >= cosU ? 1.0f : cosOutside * cosU + sinOutside * sinU;  // cos(θw − θo − θu)
  if (cosPast < 1.0f && cosPast <= n.cosFalloff) return 0.0f;
  return n.power * cosSurface * cosPast / max(dist2, 1e-30f);
}

GPU_NAMESPACE_END

#endif
