// Loading a scene for rendering: parse and validate the glTF, then put each
// primitive's triangles in the order gi::createScene gives them (Morton
// order), so triangle ids of the engine's CPU tracer and of the module's
// traversals name the same triangles.
#pragma once
#include <gi/morton.h>

#include "gltf_loader.h"

namespace engine {

inline bool loadSceneForRendering(const std::string& path, Scene& scene, std::string& error) {
  if (!loadGltf(path, scene, error)) return false;
  for (const Primitive& prim : scene.primitives)
    gi::mortonSortTriangles(std::span(&scene.positions[prim.vertexOffset].x, size_t(prim.vertexCount) * 3),
                            std::span(scene.indices).subspan(prim.firstIndex, prim.indexCount));
  return true;
}

}  // namespace engine
