// glTF 2.0 loading (tinygltf). Every problem with the file is reported as
// "FILE: what is wrong" in `error` and the function returns false; it never
// aborts on bad input.
#pragma once
#include "scene.h"

#include <string>

namespace engine {

bool loadGltf(const std::string& path, Scene& scene, std::string& error);

}  // namespace engine
