#include "bench_rays.h"

#include <chrono>
#include <cstdio>
#include <fstream>

#include "cpu_tracer.h"
#include "ray_bench.h"
#include "results_csv.h"

namespace tools {

bool benchRays(const engine::Context& ctx, const engine::Scene& scene, const engine::SceneGpu& sceneGpu,
               const gpu::GpuCamera& camera, const std::filesystem::path& dir, std::string& error) {
  struct Row {
    std::string backend;
    double primary, diffuse, shadow;
  };
  std::vector<Row> rows;
  if (ctx.rayQuery) {
    engine::RayRates r = engine::measureRayRates(ctx, sceneGpu, camera, gpu::TRAVERSAL_RAY_QUERY, error);
    rows.push_back({"rayquery", r.primary, r.diffuse, r.shadow});
  }
  engine::RayRates c = engine::measureRayRates(ctx, sceneGpu, camera, gpu::TRAVERSAL_COMPUTE, error);
  rows.push_back({"compute", c.primary, c.diffuse, c.shadow});
  if (!error.empty()) return false;
  auto buildStart = std::chrono::steady_clock::now();
  engine::CpuTracerPtr tracer = engine::createCpuTracer(scene, error);
  if (!tracer) return false;
  double embreeBuildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - buildStart).count();
  // 8 paths per pixel on the CPU: its passes are short, and the rates of the
  // extra rays come from differences of two timings.
  engine::CpuRayRates e = engine::measureCpuRayRates(*tracer, scene, camera, 8);
  rows.push_back({"embree_cpu", e.primary, e.diffuse, e.shadow});

  std::ofstream csv;
  if (!appendResultsCsv(dir / "rays.csv",
                        "scene,width,height,triangles,device,backend,primary_mrays,diffuse_mrays,shadow_mrays,"
                        "primary_of_embree,diffuse_of_embree,shadow_of_embree,bvh_build_ms\n",
                        csv, error))
    return false;
  const std::string name = std::filesystem::path(scene.sourcePath).stem().string();
  std::printf("gi-bench: bare rays on %s, %s (%zu triangles), %ux%u; Mrays/s (fraction of Embree):\n",
              ctx.properties.deviceName, name.c_str(), scene.triangleCount(), uint32_t(camera.imageSize.x),
              uint32_t(camera.imageSize.y));
  std::printf("  %-11s %16s %16s %16s\n", "backend", "primary", "diffuse", "shadow");
  const gi::SceneInfo info = gi::sceneInfo(sceneGpu.scene);  // the compute BVH's build times
  for (const Row& r : rows) {
    auto of = [](double v, double ceiling) { return ceiling > 0.0 ? v / ceiling : 0.0; };
    double buildMs = r.backend == "compute"      ? info.bvhBottomBuildMs + info.bvhTopBuildMs
                     : r.backend == "embree_cpu" ? embreeBuildMs
                                                 : 0.0;
    std::printf("  %-11s %8.3f (%4.2f) %8.3f (%4.2f) %8.3f (%4.2f)\n", r.backend.c_str(), r.primary,
                of(r.primary, e.primary), r.diffuse, of(r.diffuse, e.diffuse), r.shadow, of(r.shadow, e.shadow));
    csv << name << ',' << uint32_t(camera.imageSize.x) << ',' << uint32_t(camera.imageSize.y) << ','
        << scene.triangleCount() << ",\"" << ctx.properties.deviceName << "\"," << r.backend << ',' << r.primary << ','
        << r.diffuse << ',' << r.shadow << ',' << of(r.primary, e.primary) << ',' << of(r.diffuse, e.diffuse) << ','
        << of(r.shadow, e.shadow) << ',' << buildMs << '\n';
  }
  std::printf("  compute BVH build: %.1f ms bottom levels (once), %.2f ms top level (per transform change)\n",
              info.bvhBottomBuildMs, info.bvhTopBuildMs);
  return true;
}

}  // namespace tools
