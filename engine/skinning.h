// glTF skins on the device: each frame skinning.comp poses the skinned meshes
// from their bind pose and the frame's joint matrices, and the GI module takes
// the posed vertices from the engine's buffers (gi::updateMeshVertices with
// device streams): no CPU round trip. The G-buffer's raster reads the module's
// scene, so it draws the same pose.
#pragma once
#include <vector>

#include "scene.h"
#include "scene_gpu.h"

namespace engine {

// Nothing is created for a scene without skinned meshes (createSceneGpu calls it). Errors as in vk.h.
bool createSkinningGpu(const Context& ctx, const Scene& scene, SkinningGpu& out, std::string& error);
void destroySkinningGpu(const Context& ctx, SkinningGpu& skinning);

// Records into `cmd` the write of scene.gltf.jointMatrices, every skinned mesh posed by them and handed to
// the module (gi::updateMeshVertices); recordSceneTransformUpdate calls it. Frames in flight keep theirs.
gi::Error recordSkinning(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu);

}  // namespace engine
