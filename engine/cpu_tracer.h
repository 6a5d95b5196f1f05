// Embree's own traversal on the CPU: the machine's ray-tracing ceiling in
// gi-bench, and an answer independent of both GPU backends in the traversal
// tests. Every instance's triangles are placed in world space (one Embree
// geometry per instance and primitive); alpha masks are not applied.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <memory>

#include "scene.h"
#include "shared/gpu_scene.h"

namespace engine {

struct CpuTracer;
struct CpuTracerDeleter {
  void operator()(CpuTracer* t) const;
};
using CpuTracerPtr = std::unique_ptr<CpuTracer, CpuTracerDeleter>;

// Throws std::runtime_error if Embree fails.
CpuTracerPtr createCpuTracer(const Scene& scene, std::string& error);  // null with `error` on failure

struct CpuHit {
  float t = -1.0f;  // < 0: miss
  uint32_t instance = 0, geometry = 0, triangle = 0;
  glm::vec2 barycentrics{0.0f};     // weights of v1 and v2, as ray queries report them
  glm::vec3 geometricNormal{0.0f};  // world space, unnormalised
};

CpuHit cpuTraceClosest(const CpuTracer& tracer, glm::vec3 origin, glm::vec3 direction, float tMin, float tMax);
bool cpuTraceVisible(const CpuTracer& tracer, glm::vec3 origin, glm::vec3 direction, float tMin, float tMax);

// Mrays/s of camera rays, then diffuse bounces and shadow rays to random points
// in the scene bounds from their hits (the GPU ray bench's kinds), on every
// hardware thread, `pathsPerPixel` paths per pixel.
struct CpuRayRates {
  double primary = 0.0, diffuse = 0.0, shadow = 0.0;
};
CpuRayRates measureCpuRayRates(const CpuTracer& tracer, const Scene& scene, const gpu::GpuCamera& camera,
                               uint32_t pathsPerPixel = 2);

}  // namespace engine
