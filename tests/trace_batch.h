// The traversal tests' GPU oracle: traces a list of rays with a chosen traversal backend
// (shaders/tests/trace_batch.comp): closest hit and visibility per ray, for tests that need hits, not
// images (the CPU oracle is engine/cpu_tracer.h, Embree).
#pragma once
#include <span>
#include <vector>

#include "scene_gpu.h"
#include "shared/trace_batch.h"

namespace oracle {

// `traversal` is gpu::TRAVERSAL_*; ray queries need ctx.rayQuery. Waits.
std::vector<gpu::TraceBatchResult> traceBatch(const engine::Context& ctx, const engine::SceneGpu& scene,
                                              uint32_t traversal, std::span<const gpu::TraceBatchRay> rays);

}  // namespace oracle
