// The scene's modes that the module's public header names (gi::SceneDesc, gi::SceneCreateDesc) and the
// shaders branch on: the scene facts every set-0 pipeline is specialised on, how set 0 is traced and how
// next-event estimation picks punctual lights. No GLM.
#ifndef GI_SCENE_MODES_H
#define GI_SCENE_MODES_H
#include "gpu_macros.h"

// Specialisation constant ids every scene-reading pipeline receives (0/1 values).
#define SCENE_SPEC_HAS_EMISSIVE 0
#define SCENE_SPEC_HAS_PUNCTUAL 1
#define SCENE_SPEC_HAS_ALPHA_MASK 2
#define SCENE_SPEC_HAS_SKY 3
#define SCENE_SPEC_COUNT 4

GPU_NAMESPACE_BEGIN

// How rays are traced (trace.glsl): the SPIR-V variant a pipeline is built from.
GPU_CONST TRAVERSAL_RAY_QUERY = 0u;  // VK_KHR_ray_query against the TLAS
GPU_CONST TRAVERSAL_COMPUTE = 1u;    // our BVH, walked in the shader (GI_TRACE_COMPUTE)

// How next-event estimation treats the punctual lights (gi::SceneCreateDesc::lightSampler).
GPU_CONST LIGHT_SAMPLER_ALL = 0u;    // a shadow ray to every light at every vertex: exact, cost ∝ lights
GPU_CONST LIGHT_SAMPLER_POWER = 1u;  // one light a vertex, picked by its power: cost independent of the count
GPU_CONST LIGHT_SAMPLER_TREE = 2u;   // one light from each subtree of a cut of the tree of the point and spot
                                     // lights (GpuLightNode), picked down it by power over distance² and the
                                     // angle to the surface: exact with no more lights than the cut has subtrees

GPU_NAMESPACE_END

#endif
