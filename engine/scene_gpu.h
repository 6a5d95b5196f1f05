// The scene on the GPU: the engine's textures, and the GI module's scene
// (gi/scene.h) built from the loaded glTF through the module's public API:
// geometry, materials, lights, the sky, the acceleration structures and set 0
// (layout in shaders/shared/gpu_scene.h), which the engine's own passes (the
// G-buffer, the reference path tracer) bind too.
#pragma once
#include <array>
#include <string>

#include "compute_program.h"
#include "descriptors.h"
#include "gi/scene.h"
#include "resources.h"
#include "scene.h"

#include "shared/gpu_scene.h"

namespace engine {

// glTF skins on the device (engine/skinning.h): none for a scene without skinned meshes.
struct SkinningGpu {
  ComputeProgram program;
  Buffer bindPositions, bindNormals, joints, weights;  // per scene vertex, uploaded once
  Buffer jointMatrices;                                // written in each frame's command buffer
  Buffer positions, normals;                           // the posed vertices, per scene vertex
};

struct SceneGpu {
  std::vector<Image> textures;  // the engine's, sampled through `sampler`
  VkSampler sampler = VK_NULL_HANDLE;
  gi::Scene* scene = nullptr;  // the module's
  gi::SceneDesc desc;          // its facts; traversal = how the engine's users trace (ctx.traversalId())
  struct {
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
  } set;  // set 0
  SkinningGpu skinning;

  bool hasEmissiveTriangles() const { return desc.hasEmissiveTriangles; }
  bool hasPunctualLights() const { return desc.hasPunctualLights; }

  // Values for the SCENE_SPEC_* specialisation constants: the module's (gi::sceneSpecialization).
  std::array<uint32_t, SCENE_SPEC_COUNT> specialization() const { return gi::sceneSpecialization(desc); }
};

// Expects a scene whose primitives
// are numbered mesh by mesh (as the loader does: the module's geometry
// indices are then the scene's primitive indices). Uploads and builds; waits.
// Throws std::runtime_error with the module's message when it refuses the scene. `deviceMemory`: the
// scene's buffers and images from an allocator of the caller's (gi::SceneCreateDesc::deviceMemory).
// False with a sentence naming the file and the problem (the module's error) when the scene cannot be made.
bool createSceneGpu(const Context& ctx, const Scene& scene, SceneGpu& gpu, std::string& error,
                    const gi::DeviceMemoryCallbacks& deviceMemory = {});
void destroySceneGpu(const Context& ctx, SceneGpu& gpu);

// For moving instances and lights: hands the module `scene`'s transforms and
// punctual lights (gi::updateInstances, gi::updateLights), which record the
// tables' writes and the TLAS rebuild into `cmd`, and skins the skinned meshes
// with scene.gltf.jointMatrices (engine/skinning.h): frames in flight keep theirs.
// False with the module's error (the scene's file first) when an update is refused.
bool recordSceneTransformUpdate(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu,
                                std::string& error);
// The first frame the scene stands still after moving (an animation paused): its instances' previous
// transforms and its deformable meshes' previous positions become the current ones
// (gi::updateInstances with the same transforms, gi::holdMeshVertices), so the G-buffer's motion vectors
// read no motion; nothing is skinned or refit.
bool recordSceneHold(VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu, std::string& error);
// For a deformable mesh (Mesh::deformable): hands the module `scene`'s vertices of mesh `mesh`
// (gi::updateMeshVertices), which records their write, the BVH's refit and the BLAS update into `cmd`.
bool recordMeshVertexUpdate(VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu, uint32_t mesh, std::string& error);

}  // namespace engine
