// Loading a scene for rendering: parse and validate the glTF, then Morton-sort
// triangles and instances for faster acceleration structures.
#pragma once
#include "gltf_loader.h"
#include "morton.h"

namespace engine {

inline bool loadSceneForRendering(const std::string& path, Scene& scene, std::string& error) {
  if (!loadGltf(path, scene, error)) return false;
  mortonSortScene(scene);
  return true;
}

}  // namespace engine
