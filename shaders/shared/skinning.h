// Interface of skinning.comp: the engine's linear-blend skinning of glTF
// skins (engine/skinning.h). Every buffer is reached through its device
// address; vertex i of a dispatch is scene vertex first + i.
#ifndef GI_SKINNING_H
#define GI_SKINNING_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

#define SKINNING_GROUP_SIZE 64u

struct SkinningPush {
  uvec2 bindPositions;  // vec3[] (packed floats), the file's pose, per scene vertex
  uvec2 bindNormals;    // vec3[]
  uvec2 joints;         // uvec4[]: a vertex's four joints, within its skin
  uvec2 weights;        // vec4[]: their weights (sum 1)
  uvec2 jointMatrices;  // mat4[]: world × inverse bind, every skin's in turn
  uvec2 positions;      // vec3[] written: the posed vertices, per scene vertex
  uvec2 normals;        // vec3[] written
  uint first;           // the dispatch's first scene vertex
  uint count;
  uint firstJoint;      // its skin's first matrix in jointMatrices
  uint pad0;
};
GPU_ASSERT_SIZE(SkinningPush, 72);

GPU_NAMESPACE_END

#endif
