// gi-bench --rays: the bare-ray microbenchmark for every traversal backend
// the device has and for Embree on the CPU (the machine's ceiling), in one run.
#pragma once
#include <filesystem>
#include <string>

#include "scene_gpu.h"

namespace tools {

// Prints a table, appends rows to DIR/rays.csv (header written when the file
// is new). Returns false with `error` set if a file cannot be written.
bool benchRays(const engine::Context& ctx, const engine::Scene& scene, const engine::SceneGpu& sceneGpu,
               const gpu::GpuCamera& camera, const std::filesystem::path& dir, std::string& error);

}  // namespace tools
