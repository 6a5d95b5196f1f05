// Traces a list of rays on the GPU with a chosen traversal backend
// (trace_batch.comp): closest hit and visibility per ray. For the traversal
// tests and tools that need hits, not images.
#pragma once
#include <span>
#include <vector>

#include "scene_gpu.h"
#include "shared/trace_batch.h"

namespace engine {

// `traversal` is gpu::TRAVERSAL_*; ray queries need ctx.rayQuery. Waits.
std::vector<gpu::TraceBatchResult> traceBatch(const Context& ctx, const SceneGpu& scene, uint32_t traversal,
                                              std::span<const gpu::TraceBatchRay> rays);

}  // namespace engine
