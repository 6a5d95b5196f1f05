// The module's compute programs: which ones a method's settings run (one
// list, read by creation, by the warm-up and by gi::programNames), their
// creation, and the warm-up that lets a driver compiling at first dispatch
// (lavapipe) compile them off the frame.
#pragma once
#include <span>
#include <vector>

#include "module.h"

namespace gi {

// The descriptor sets a program binds.
enum class ProgramSets : uint32_t {
  Frame,         // set 0 (the scene) and set 1 (the frame)
  FrameAndHash,  // and set 2 (the hash map)
  Filter,        // the screen filters' one set
};

struct ProgramUse {
  const char* name;                 // its shader's name: "hpsf_insert", "gif_box", ...
  vk::ComputeProgram* program;      // where the module keeps it
  std::span<const uint32_t> spirv;  // the variant for the scene's traversal
  uint32_t pushSize;
  glm::uvec2 group;
  ProgramSets sets;
};

// Every program `settings` run on the module's scene, in recording order.
std::vector<ProgramUse> programsFor(Module& m, const Settings& settings);
// Creates those of `settings` not created yet. ensurePrograms takes
// m.programsMutex; createPrograms is for a caller that holds it.
vk::Status ensurePrograms(Module& m, const Settings& settings);
vk::Status createPrograms(Module& m, const Settings& settings);
// The programs specialised on the scene (setScene rebuilds them).
std::vector<vk::ComputeProgram*> scenePrograms(Module& m);
// Everything programs.cpp created: programs, the hash set layout, the warm-up's placeholders.
void destroyPrograms(Module& m);

}  // namespace gi
