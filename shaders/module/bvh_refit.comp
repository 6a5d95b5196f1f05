#version 460
// Refits the compute traversal's BVH to a deformable mesh's new vertices
// (shared/bvh_refit.h): its triangles first, then its bottom level's nodes a
// level at a time from the deepest (one dispatch each, a barrier between),
// then the top level. Refitting keeps the tree's shape, so traversal stays
// exact (every box still holds its triangles) while its quality drifts with
// the deformation (gi::updateMeshVertices rebuilds it on the CPU instead where
// that drift passes SceneCreateDesc::rebuildCostRatio).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/bvh_refit.h"
#include "shared/gpu_bvh.h"
#include "shared/gpu_scene.h"

layout(local_size_x = REFIT_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { RefitPush pc; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Floats { float v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Uints { uint v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Geometries { GpuGeometry v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) buffer Triangles { GpuBvhTriangle v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) buffer Nodes { GpuBvhNode v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Instances { GpuBvhInstance v[]; };

const float kHuge = 3.402823e38;  // an empty box: lo = +kHuge, hi = −kHuge
uint64_t address(uvec2 a) { return packUint2x32(a); }

vec3 position(uint vertex) {
  Floats p = Floats(address(pc.positions));
  return vec3(p.v[3u * vertex], p.v[3u * vertex + 1u], p.v[3u * vertex + 2u]);
}

void refitTriangle(uint slot) {
  Triangles triangles = Triangles(address(pc.triangles));
  const GpuBvhTriangle t = triangles.v[slot];
  const GpuGeometry g = Geometries(address(pc.geometries)).v[t.geometry];
  Uints indices = Uints(address(pc.indices));
  const uint first = g.firstIndex + 3u * t.triangle;
  const vec3 a = position(indices.v[first] + g.vertexOffset);
  const vec3 b = position(indices.v[first + 1u] + g.vertexOffset);
  const vec3 c = position(indices.v[first + 2u] + g.vertexOffset);
  triangles.v[slot].v0 = a;
  triangles.v[slot].edge1 = b - a;
  triangles.v[slot].edge2 = c - a;
}

// The box of a child reference: a leaf's triangles, or an inner node's four boxes.
void childBox(Nodes nodes, uint ref, out vec3 lo, out vec3 hi) {
  lo = vec3(kHuge);
  hi = vec3(-kHuge);
  if ((ref & BVH_LEAF_BIT) != 0u) {
    Triangles triangles = Triangles(address(pc.triangles));
    const uint first = ref & BVH_LEAF_FIRST_MASK, count = ((ref >> BVH_LEAF_COUNT_SHIFT) & 0xfu) + 1u;
    for (uint i = 0u; i < count; ++i) {
      const GpuBvhTriangle t = triangles.v[first + i];
      lo = min(lo, min(t.v0, min(t.v0 + t.edge1, t.v0 + t.edge2)));
      hi = max(hi, max(t.v0, max(t.v0 + t.edge1, t.v0 + t.edge2)));
    }
    return;
  }
  const GpuBvhNode n = nodes.v[ref];
  for (uint k = 0u; k < BVH_WIDTH; ++k) {
    if (n.child[k] == BVH_NO_CHILD) continue;
    lo = min(lo, vec3(n.minX[k], n.minY[k], n.minZ[k]));
    hi = max(hi, vec3(n.maxX[k], n.maxY[k], n.maxZ[k]));
  }
}

void setBox(Nodes nodes, uint index, uint k, vec3 lo, vec3 hi) {
  nodes.v[index].minX[k] = lo.x;
  nodes.v[index].minY[k] = lo.y;
  nodes.v[index].minZ[k] = lo.z;
  nodes.v[index].maxX[k] = hi.x;
  nodes.v[index].maxY[k] = hi.y;
  nodes.v[index].maxZ[k] = hi.z;
}

void refitNode(uint index) {
  Nodes nodes = Nodes(address(pc.nodes));
  const uvec4 child = nodes.v[index].child;
  for (uint k = 0u; k < BVH_WIDTH; ++k) {
    if (child[k] == BVH_NO_CHILD) continue;
    vec3 lo, hi;
    childBox(nodes, child[k], lo, hi);
    setBox(nodes, index, k, lo, hi);
  }
}

// A top-level leaf's world box: its instance's bottom root box, its eight corners placed in the world.
void instanceBox(uint ref, out vec3 lo, out vec3 hi) {
  const GpuBvhInstance inst = Instances(address(pc.topInstances)).v[ref & BVH_LEAF_FIRST_MASK];
  vec3 objectLo, objectHi;
  childBox(Nodes(address(pc.nodes)), inst.root, objectLo, objectHi);
  const mat3 objectFromWorld = transpose(mat3(inst.objectFromWorld0.xyz, inst.objectFromWorld1.xyz, inst.objectFromWorld2.xyz));
  const vec3 translation = vec3(inst.objectFromWorld0.w, inst.objectFromWorld1.w, inst.objectFromWorld2.w);
  const mat3 worldFromObject = inverse(objectFromWorld);
  lo = vec3(kHuge);
  hi = vec3(-kHuge);
  for (uint c = 0u; c < 8u; ++c) {
    const vec3 corner = vec3((c & 1u) != 0u ? objectHi.x : objectLo.x, (c & 2u) != 0u ? objectHi.y : objectLo.y,
                             (c & 4u) != 0u ? objectHi.z : objectLo.z);
    const vec3 world = worldFromObject * (corner - translation);
    lo = min(lo, world);
    hi = max(hi, world);
  }
}

void refitTop() {
  Nodes top = Nodes(address(pc.topNodes));
  for (uint i = pc.count; i-- > 0u;) {
    const uvec4 child = top.v[i].child;
    for (uint k = 0u; k < BVH_WIDTH; ++k) {
      if (child[k] == BVH_NO_CHILD) continue;
      vec3 lo, hi;
      if ((child[k] & BVH_LEAF_BIT) != 0u) instanceBox(child[k], lo, hi);
      else childBox(top, child[k], lo, hi);
      setBox(top, i, k, lo, hi);
    }
  }
}

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (pc.mode == REFIT_TOP) {
    if (i == 0u) refitTop();
    return;
  }
  if (i >= pc.count) return;
  if (pc.mode == REFIT_TRIANGLES) refitTriangle(pc.first + i);
  else refitNode(Uints(address(pc.order)).v[pc.first + i]);
}
