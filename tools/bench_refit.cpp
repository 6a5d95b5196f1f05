#include "bench_refit.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>
#include <vector>

#include "camera.h"
#include "deformed_grid.h"
#include "gi/scene.h"
#include "gpu_timer.h"
#include "ray_bench.h"
#include "results_csv.h"
#include "scene_gpu.h"

namespace tools {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A square grid of at least `triangles` triangles in the xz plane, 1 m wide, facing up.
struct Grid {
  std::vector<glm::vec3> rest, positions, normals;
  std::vector<uint32_t> indices;
};
Grid makeGrid(uint32_t triangles) {
  const uint32_t side = std::max(1u, uint32_t(std::ceil(std::sqrt(double(triangles) / 2.0))));
  Grid g;
  for (uint32_t z = 0; z <= side; ++z)
    for (uint32_t x = 0; x <= side; ++x) {
      g.rest.push_back({float(x) / float(side) - 0.5f, 0.0f, float(z) / float(side) - 0.5f});
      g.normals.push_back({0.0f, 1.0f, 0.0f});
    }
  for (uint32_t z = 0; z < side; ++z)
    for (uint32_t x = 0; x < side; ++x) {
      const uint32_t a = z * (side + 1) + x, b = a + 1, c = a + side + 1, d = c + 1;
      g.indices.insert(g.indices.end(), {a, c, b, b, c, d});
    }
  g.positions = g.rest;
  return g;
}

// The grid waved: a ripple of `phase` (every vertex moves, the bounds barely change).
void wave(Grid& g, float phase) {
  for (size_t v = 0; v < g.rest.size(); ++v) {
    const glm::vec3 r = g.rest[v];
    g.positions[v] = r + glm::vec3(0.0f, 0.05f * std::sin(12.0f * r.x + phase) * std::cos(9.0f * r.z + phase), 0.0f);
  }
}

struct Timed {
  double cpuMs = 0.0, gpuMs = 0.0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Records `record` into a command buffer between a timestamp pair, submits and waits (errors as in
// engine/vk.h: nothing runs once `error` is set).
template <typename F>
Timed timed(const engine::Context& ctx, engine::GpuTimer& timer, std::string& error, F&& record) {
  Timed t;
  if (!error.empty()) return t;
  engine::resetGpuTimer(ctx, timer);
  engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        engine::beginPass(ctx, cmd, timer, "update");
        engine::timestampFence(cmd);
        const Clock::time_point start = Clock::now();
        record(cmd);
        t.cpuMs = msSince(start);
        engine::endPass(ctx, cmd, timer);
      },
      error);
  for (const engine::PassTime& p : engine::readPassTimes(ctx, timer, error)) t.gpuMs += p.ms;
  return t;
}

// A module error kept as the run's first failure.
void note(const gi::Error& e, std::string& error) {
  if (e && error.empty()) error = e.message;
}

struct RefitRow {
  std::vector<double> refitCpu, refitGpu, rebuildCpu, rebuildGpu;
};

// The grid's scene description for `backend` (pointers into `grid`, `mesh` and the other arguments).
gi::SceneCreateDesc gridScene(const engine::Context& ctx, uint32_t backend) {
  gi::SceneCreateDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;
  desc.instance = ctx.instance;
  desc.physicalDevice = ctx.physicalDevice;
  desc.device = ctx.device;
  desc.traversal = gi::Traversal(backend);
  // With ray queries, the compute BVH too: the refit and the BLAS update, as RESULTS' refit table was
  // measured (a scene for ray queries alone pays the BLAS update and the TLAS rebuild only).
  desc.bothTraversals = backend == gpu::TRAVERSAL_RAY_QUERY;
  return desc;
}

// Rebuild (a new scene in each pose, of a mesh not declared deformable: what a module without refits would
// need every frame) against refit (one scene, a new pose a frame; two untimed first: compilation at the
// first dispatch).
bool measureGrid(const engine::Context& ctx, engine::GpuTimer& timer, Grid& grid, uint32_t backend, RefitRow& row,
                 std::string& error) {
  const gi::PrimitiveDesc primitive{0, uint32_t(grid.indices.size()), 0, uint32_t(grid.rest.size()), 0};
  gi::MaterialDesc material;
  gi::LightDesc light;
  light.position[1] = 2.0f;
  gi::MeshDesc mesh;
  mesh.positions = &grid.positions[0].x;
  mesh.normals = &grid.normals[0].x;
  mesh.vertexCount = uint32_t(grid.rest.size());
  mesh.indices = grid.indices.data();
  mesh.indexCount = uint32_t(grid.indices.size());
  mesh.primitives = std::span(&primitive, 1);
  gi::InstanceDesc instance;
  gi::SceneContents contents;
  contents.meshes = std::span(&mesh, 1);
  contents.materials = std::span(&material, 1);
  contents.lights = std::span(&light, 1);
  contents.instances = std::span(&instance, 1);
  const gi::SceneCreateDesc desc = gridScene(ctx, backend);
  mesh.deformable = false;
  for (int i = 0; i < 3 && error.empty(); ++i) {
    wave(grid, float(i));
    gi::Scene* scene = nullptr;
    const Timed t = timed(ctx, timer, error,
                          [&](VkCommandBuffer cmd) { note(gi::createScene(desc, contents, cmd, scene), error); });
    if (scene) note(gi::finishSceneUpload(scene), error);
    row.rebuildCpu.push_back(t.cpuMs);
    row.rebuildGpu.push_back(t.gpuMs);
    gi::destroyScene(scene);
  }
  mesh.deformable = true;
  gi::Scene* scene = nullptr;
  engine::submitAndWait(
      ctx, [&](VkCommandBuffer cmd) { note(gi::createScene(desc, contents, cmd, scene), error); }, error);
  if (scene) note(gi::finishSceneUpload(scene), error);
  for (int i = 0; i < 7 && error.empty(); ++i) {
    wave(grid, 0.5f * float(i));
    gi::MeshVertices vertices;
    vertices.positions = &grid.positions[0].x;
    vertices.normals = &grid.normals[0].x;
    const Timed t = timed(ctx, timer, error,
                          [&](VkCommandBuffer cmd) { note(gi::updateMeshVertices(scene, cmd, 0, vertices), error); });
    if (i < 2) continue;
    row.refitCpu.push_back(t.cpuMs);
    row.refitGpu.push_back(t.gpuMs);
  }
  gi::destroyScene(scene);
  return error.empty();
}

}  // namespace

bool benchRefit(const engine::Context& ctx, std::span<const uint32_t> triangleCounts, const std::filesystem::path& dir,
                std::string& error) {
  std::ofstream csv;
  if (!appendResultsCsv(dir / "refit.csv",
                        "device,backend,triangles,refit_cpu_ms,refit_gpu_ms,rebuild_cpu_ms,rebuild_gpu_ms\n", csv,
                        error))
    return false;
  std::vector<uint32_t> backends{gpu::TRAVERSAL_COMPUTE};
  if (ctx.rayQuery) backends.push_back(gpu::TRAVERSAL_RAY_QUERY);
  engine::GpuTimer timer = engine::createGpuTimer(ctx, error, 4);
  std::printf(
      "gi-bench: a deforming grid on %s: ms a frame, refit (updateMeshVertices) against rebuild (createScene)\n",
      ctx.properties.deviceName);
  std::printf("  %-9s %10s %12s %12s %14s %14s\n", "backend", "triangles", "refit CPU", "refit GPU", "rebuild CPU",
              "rebuild GPU");
  for (uint32_t count : triangleCounts)
    for (uint32_t backend : backends) {
      Grid grid = makeGrid(count);
      RefitRow row;
      if (!measureGrid(ctx, timer, grid, backend, row, error)) break;
      const char* name = backend == gpu::TRAVERSAL_COMPUTE ? "compute" : "rayquery";
      const uint32_t triangles = uint32_t(grid.indices.size() / 3);
      std::printf("  %-9s %10u %12.2f %12.2f %14.2f %14.2f\n", name, triangles, median(row.refitCpu),
                  median(row.refitGpu), median(row.rebuildCpu), median(row.rebuildGpu));
      csv << '"' << ctx.properties.deviceName << "\"," << name << ',' << triangles << ',' << median(row.refitCpu) << ','
          << median(row.refitGpu) << ',' << median(row.rebuildCpu) << ',' << median(row.rebuildGpu) << '\n';
    }
  engine::destroyGpuTimer(ctx, timer);
  return error.empty();
}

namespace {

// The grid alone under a camera looking down at the part the fold stacks the rest on, 320×180, and its mesh.
engine::Scene foldScene(uint32_t& grid, gpu::GpuCamera& camera) {
  engine::Scene scene;
  scene.sourcePath = "folded grid";
  engine::Material grey;
  grey.baseColor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
  grey.metallic = 0.0f;
  scene.materials.push_back(grey);
  grid = appendGrid(scene, 100, glm::vec3(0.0f), 1.0f);
  engine::Camera view;  // on the strip the fold stacks the others on (x from −0.5 to −0.375), from above
  const glm::vec3 target(-0.4375f, 0.0f, 0.0f);
  view.worldFromView = glm::inverse(glm::lookAt(target + glm::vec3(0.0f, 0.5f, 0.05f), target, glm::vec3(1, 0, 0)));
  view.yfov = 0.5f;
  scene.cameras.push_back(view);
  scene.rebuildCostRatio = 0.0f;  // refits only: what they cost is measured
  camera = engine::makeGpuCamera(view, 320, 180, nullptr);
  return scene;
}

}  // namespace

bool benchRefitQuality(const engine::Context& ctx, const std::filesystem::path& dir, std::string& error) {
  std::ofstream csv;
  if (!appendResultsCsv(dir / "refit_quality.csv",
                        "device,backend,triangles,fold,cost_ratio,refit_primary_mrays,built_primary_mrays\n", csv,
                        error))
    return false;
  uint32_t grid = 0;
  gpu::GpuCamera camera{};
  engine::Scene scene = foldScene(grid, camera);
  scene.bothTraversals = ctx.rayQuery;
  const std::vector<glm::vec3> rest = scene.positions;
  engine::SceneGpu refit;
  if (!engine::createSceneGpu(ctx, scene, refit, error)) return false;
  std::vector<uint32_t> backends{gpu::TRAVERSAL_COMPUTE};
  if (ctx.rayQuery) backends.push_back(gpu::TRAVERSAL_RAY_QUERY);
  // Camera rays, 4 a pixel, 7 timed rounds (each after an untimed one; the programs compile at their first
  // dispatch); the better of two such runs, the two scenes' runs interleaved (the machine's other work
  // only slows a run down).
  auto primary = [&](const engine::SceneGpu& gpu, uint32_t backend) {
    return engine::runRayBench(ctx, gpu, camera, gpu::RB_KIND_PRIMARY, backend, error, 4, 7).mraysPerSecond();
  };
  std::printf("gi-bench: a grid of %zu triangles folded on %s: camera Mrays/s, refit / built anew\n",
              scene.indices.size() / 3, ctx.properties.deviceName);
  std::printf("  %-9s %5s %10s %16s\n", "backend", "fold", "cost ratio", "Mrays/s");
  for (float fold : {0.0f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f}) {
    foldGrid(scene, grid, rest, 8, fold, 0.0f);
    engine::submitAndWait(
        ctx, [&](VkCommandBuffer cmd) { engine::recordMeshVertexUpdate(cmd, scene, refit, grid, error); }, error);
    const float ratio = gi::sceneInfo(refit.scene).refitCostRatio;
    engine::SceneGpu built;  // the same pose built anew (a deformable level, as a rebuild makes it)
    if (!error.empty() || !engine::createSceneGpu(ctx, scene, built, error)) break;
    for (uint32_t backend : backends) {
      double r = 0.0, b = 0.0;
      for (int run = 0; run < 2; ++run) {
        r = std::max(r, primary(refit, backend));
        b = std::max(b, primary(built, backend));
      }
      const char* name = backend == gpu::TRAVERSAL_COMPUTE ? "compute" : "rayquery";
      std::printf("  %-9s %5.2f %10.2f %7.2f / %6.2f\n", name, fold, ratio, r, b);
      csv << '"' << ctx.properties.deviceName << "\"," << name << ',' << scene.indices.size() / 3 << ',' << fold << ','
          << ratio << ',' << r << ',' << b << '\n';
    }
    engine::destroySceneGpu(ctx, built);
  }
  engine::destroySceneGpu(ctx, refit);
  return error.empty();
}

namespace {

// One update of `mesh` to the grid's pose `fold` (ripple `ripple`), submitted and waited for: the CPU ms
// of the module's call (and the engine's copy of the vertices it records), and the scene's facts after it.
double timedUpdate(const engine::Context& ctx, engine::Scene& scene, engine::SceneGpu& gpu, uint32_t mesh,
                   const std::vector<glm::vec3>& rest, float fold, float ripple, gi::SceneInfo& info,
                   std::string& error) {
  foldGrid(scene, mesh, rest, 8, fold, ripple);
  double ms = 0.0;
  engine::submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        const Clock::time_point start = Clock::now();
        engine::recordMeshVertexUpdate(cmd, scene, gpu, mesh, error);
        ms = msSince(start);
      },
      error);
  info = gi::sceneInfo(gpu.scene);
  return ms;
}

struct RebuildRow {
  double refitMs = 0.0, rebuildMs = 0.0, startMs = 0.0, installMs = 0.0, buildWallMs = 0.0;
  uint32_t updatesUntilInstalled = 0;
};

// A grid of `side`² quads, compute traversal: a ripple (a refit), then folded flat at once (the level
// degraded past gi::SceneCreateDesc::rebuildCostRatio's 1.5): rebuilt in that update, or started off thread
// there and installed by a later update (updates of the same pose every 5 ms until then).
bool measureRebuild(const engine::Context& ctx, uint32_t side, bool offThread, RebuildRow& row, std::string& error) {
  engine::Scene scene;
  scene.sourcePath = "folded grid";
  scene.materials.push_back(engine::Material{});
  const uint32_t mesh = appendGrid(scene, side, glm::vec3(0.0f), 1.0f);
  scene.cameras.push_back(engine::Camera{});
  scene.rebuildOffThread = offThread;
  const std::vector<glm::vec3> rest = scene.positions;
  engine::SceneGpu gpu;
  if (!engine::createSceneGpu(ctx, scene, gpu, error)) return false;
  gi::SceneInfo info;
  timedUpdate(ctx, scene, gpu, mesh, rest, 0.0f, 0.002f, info, error);  // the programs compile
  row.refitMs = timedUpdate(ctx, scene, gpu, mesh, rest, 0.0f, 0.004f, info, error);
  // Folded: a level of more than 64k triangles is measured 16k triangles an update, so the update that
  // finds it degraded may come some updates later.
  double ms = 0.0;
  for (int i = 0; i < 200 && error.empty() && !info.levelRebuildRunning && info.levelRebuilds == 0; ++i)
    ms = timedUpdate(ctx, scene, gpu, mesh, rest, 1.0f, 0.0f, info, error);
  (offThread ? row.startMs : row.rebuildMs) = ms;
  const Clock::time_point start = Clock::now();
  while (offThread && info.levelRebuilds == 0 && error.empty() && msSince(start) < 60000.0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    row.installMs = timedUpdate(ctx, scene, gpu, mesh, rest, 1.0f, 0.0f, info, error);
    row.updatesUntilInstalled++;
  }
  row.buildWallMs = msSince(start);
  if (error.empty() && info.levelRebuilds != 1)
    error = "the folded grid's level was not rebuilt (cost ratio " + std::to_string(info.refitCostRatio) + ")";
  engine::destroySceneGpu(ctx, gpu);
  return error.empty();
}

}  // namespace

bool benchRefitRebuild(const engine::Context& ctx, std::span<const uint32_t> triangleCounts,
                       const std::filesystem::path& dir, std::string& error) {
  std::ofstream csv;
  if (!appendResultsCsv(dir / "refit_rebuild.csv",
                        "device,triangles,refit_update_ms,rebuild_update_ms,start_update_ms,install_update_ms,"
                        "updates_until_installed,start_to_install_ms\n",
                        csv, error))
    return false;
  std::printf("gi-bench: the update that finds a folded grid's level degraded on %s: CPU ms\n",
              ctx.properties.deviceName);
  std::printf("  %10s %8s %16s %14s %15s %8s %14s\n", "triangles", "refit", "rebuild in it", "start (off)",
              "install (off)", "updates", "start→install");
  for (uint32_t count : triangleCounts) {
    const uint32_t side = std::max(1u, uint32_t(std::lround(std::sqrt(double(count) / 2.0))));
    RebuildRow inUpdate, offThread;
    if (!measureRebuild(ctx, side, false, inUpdate, error) || !measureRebuild(ctx, side, true, offThread, error)) break;
    const uint32_t triangles = 2 * side * side;
    std::printf("  %10u %8.2f %16.2f %14.2f %15.2f %8u %14.1f\n", triangles, offThread.refitMs, inUpdate.rebuildMs,
                offThread.startMs, offThread.installMs, offThread.updatesUntilInstalled, offThread.buildWallMs);
    csv << '"' << ctx.properties.deviceName << "\"," << triangles << ',' << offThread.refitMs << ','
        << inUpdate.rebuildMs << ',' << offThread.startMs << ',' << offThread.installMs << ','
        << offThread.updatesUntilInstalled << ',' << offThread.buildWallMs << '\n';
  }
  return error.empty();
}

}  // namespace tools
