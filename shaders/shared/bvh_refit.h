// Interface of bvh_refit.comp: refits the compute traversal's BVH (gpu_bvh.h)
// to a deformable mesh's new vertices on the device (gi::updateMeshVertices).
// Every buffer is reached through its device address: the pass binds no set.
// The tree's shape stays; its boxes and triangles follow the vertices.
#ifndef GI_BVH_REFIT_H
#define GI_BVH_REFIT_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

#define REFIT_GROUP_SIZE 64u
GPU_CONST REFIT_TRIANGLES = 0u;  // rewrite triangles [first, first + count) from the positions
GPU_CONST REFIT_NODES = 1u;      // refit the nodes order[first, first + count): one level, its children refit already
GPU_CONST REFIT_TOP = 2u;        // refit the top level, one invocation, nodes from the last to the root (children
                                 // come after their parents), its leaves from their instances' bottom roots

struct RefitPush {
  uvec2 positions;   // float[3 × vertices], object space (the scene's packed positions)
  uvec2 indices;     // uint[], relative to their geometry's vertexOffset
  uvec2 geometries;  // GpuGeometry[]
  uvec2 triangles;   // GpuBvhTriangle[], rewritten (REFIT_TRIANGLES)
  uvec2 nodes;       // GpuBvhNode[], the bottom levels, refit (REFIT_NODES) or read (REFIT_TOP)
  uvec2 order;       // uint[]: bottom node indices, level by level (REFIT_NODES)
  uvec2 topNodes;    // GpuBvhNode[], the top level (REFIT_TOP)
  uvec2 topInstances;  // GpuBvhInstance[] (REFIT_TOP)
  uint mode;         // REFIT_*
  uint first;
  uint count;        // REFIT_TOP: top-level nodes
  uint pad0;
};
GPU_ASSERT_SIZE(RefitPush, 80);

GPU_NAMESPACE_END

#endif
