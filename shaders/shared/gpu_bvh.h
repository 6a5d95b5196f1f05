// The compute traversal backend's scene: a two-level 4-wide BVH built on the CPU
// with Embree's builder (engine/bvh_builder.cpp) and walked by trace.glsl when
// it is compiled with GI_TRACE_COMPUTE. Bottom levels hold triangles in object
// space (one per mesh, plus one merged level for every static instance with an
// identity transform, whose triangles are in world space); the top level holds
// instances and is rebuilt on the CPU when transforms change.
#ifndef GI_GPU_BVH_H
#define GI_GPU_BVH_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

// A child reference: an inner node's index, or a leaf (BVH_LEAF_BIT set)
// holding BVH_LEAF_COUNT(ref) consecutive primitives from BVH_LEAF_FIRST(ref).
GPU_CONST BVH_LEAF_BIT = 0x80000000u;
GPU_CONST BVH_LEAF_COUNT_SHIFT = 27u;       // bits 27..30: count − 1
GPU_CONST BVH_MAX_LEAF_SIZE = 8u;           // primitives per bottom leaf at most; top-level leaves hold one instance
GPU_CONST BVH_LEAF_FIRST_MASK = 0x07ffffffu; // bits 0..26: the first primitive
GPU_CONST BVH_NO_CHILD = 0xffffffffu;       // an empty child (never entered)
GPU_CONST BVH_LEAVE_INSTANCE = 0xfffffffeu; // a stack marker: back to the top level (not a valid leaf: 16 > max count)
GPU_CONST BVH_STACK_SIZE = 64u;             // traversal stack entries, both levels together
GPU_CONST BVH_FROM_TOP_LEVEL = 0xffffffffu; // GpuBvhTriangle.instance: the instance comes from the top level

// An inner node of the 4-wide BVH: its children's boxes in SoA order, so one
// node read tests all four with vec4 arithmetic. Unused slots hold
// BVH_NO_CHILD (their boxes are never tested). On lavapipe 2- and 4-wide
// traced at the same rate within noise from storage buffers; reading the
// nodes as texel buffers is what made the difference (docs/RESULTS.md).
GPU_CONST BVH_WIDTH = 4u;
struct GpuBvhNode {
  vec4 minX;
  vec4 minY;
  vec4 minZ;
  vec4 maxX;
  vec4 maxY;
  vec4 maxZ;
  uvec4 child;  // child references
};
GPU_ASSERT_SIZE(GpuBvhNode, 112);

// A triangle ready for Möller–Trumbore: v0 and the two edges, with the ids a
// hit reports (the same ids ray queries give).
struct GpuBvhTriangle {
  vec3 v0;
  uint geometry;  // absolute geometry index (GpuGeometry)
  vec3 edge1;     // v1 − v0
  uint triangle;  // within the geometry
  vec3 edge2;     // v2 − v0
  uint instance;  // scene instance, or BVH_FROM_TOP_LEVEL
};
GPU_ASSERT_SIZE(GpuBvhTriangle, 48);

// A top-level primitive: one bottom level placed in the world.
struct GpuBvhInstance {
  vec4 objectFromWorld0;  // rows of the 3×4 inverse transform
  vec4 objectFromWorld1;
  vec4 objectFromWorld2;
  uint root;              // the bottom level's root node (an index into the bottom nodes)
  uint instance;          // scene instance (the merged static level's triangles carry their own)
  uint pad0;
  uint pad1;
};
GPU_ASSERT_SIZE(GpuBvhInstance, 64);

GPU_NAMESPACE_END
#endif
