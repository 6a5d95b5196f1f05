// The compute traversal backend against ray queries and against Embree's own
// traversal on the CPU (a third, independent answer): for the same rays, the
// same closest hit (instance and triangle, except exact ties on shared
// edges, t within 1e-5 relative) and the same visibility. Rays: camera rays,
// diffuse bounces from the hits and shadow segments to random points, on the
// shipped scenes, after an instance moved, on alpha-masked geometry, at
// millimetre and hundred-kilometre scale and with degenerate triangles.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <functional>
#include <random>
#include <set>
#include <thread>
#include <tuple>

#include "cpu_tracer.h"
#include "deformed_grid.h"
#include "gpu_test.h"
#include "scene/bvh_builder.h"
#include "scene/prepared_level.h"
#include "scene/refit.h"
#include "trace_batch.h"

namespace {

// Rays for one scene: every pixel's camera ray, then a diffuse bounce and a
// shadow segment from each camera ray's hit (found with Embree).
std::vector<gpu::TraceBatchRay> makeRays(const engine::Scene& scene, const engine::CpuTracer& tracer, uint32_t w,
                                         uint32_t h) {
  gpu::GpuCamera cam = engine::makeGpuCamera(scene.cameras[0], w, h, nullptr);
  engine::Bounds bounds = scene.worldBounds();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<gpu::TraceBatchRay> rays;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      glm::vec3 dir = gpu::giCameraRayDirection(cam, glm::vec2(float(x), float(y)) + 0.5f);
      rays.push_back({cam.position, 0.0f, dir, 1e30f});
      engine::CpuHit hit = engine::cpuTraceClosest(tracer, cam.position, dir, 0.0f, 1e30f);
      if (hit.t < 0.0f) continue;
      glm::vec3 n = glm::normalize(hit.geometricNormal);
      if (glm::dot(n, dir) > 0.0f) n = -n;
      glm::vec3 p = cam.position + hit.t * dir;
      float eps = 1e-4f * std::max(1.0f, bounds.extent());
      glm::vec3 origin = p + eps * n;
      // Near an edge the offset origin can lie on the neighbouring surface
      // (a wall's hit point moved onto the ceiling's plane): whether t = 0
      // is a hit is then the implementation's choice, so secondary rays
      // start a hundredth of the offset out.
      const float tMin = 0.01f * eps;
      glm::vec3 bounce = glm::normalize(n + glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f)));
      if (std::isfinite(bounce.x)) rays.push_back({origin, tMin, bounce, 1e30f});
      glm::vec3 target = glm::mix(bounds.min, bounds.max, glm::vec3(u(rng), u(rng), u(rng)));
      float distance = glm::length(target - origin);
      if (distance > tMin) rays.push_back({origin, tMin, (target - origin) / distance, distance});
    }
  return rays;
}

struct Agreement {
  size_t rays = 0, hitMissDiffer = 0, tieDiffer = 0, tDiffer = 0, visibleDiffer = 0, hits = 0;
};

// t within 1e-5 relative to the larger of t and the origin's largest
// coordinate: a hit point is known only to float precision of its
// coordinates, so a hit a few millimetres from an origin a metre from the
// world's centre has a larger relative error in t, in every implementation.
bool closeT(float a, float b, float originScale) {
  return std::abs(a - b) <= 1e-5f * std::max({std::abs(a), std::abs(b), originScale});
}

Agreement compare(const std::vector<gpu::TraceBatchResult>& a, const std::vector<gpu::TraceBatchResult>& b,
                  const std::vector<gpu::TraceBatchRay>& rays) {
  std::vector<float> scale;
  for (const gpu::TraceBatchRay& r : rays) {
    glm::vec3 o = glm::abs(r.origin);
    scale.push_back(std::max({o.x, o.y, o.z}) / glm::length(r.direction));
  }
  Agreement g;
  g.rays = a.size();
  for (size_t i = 0; i < a.size(); ++i) {
    bool hitA = a[i].t >= 0.0f, hitB = b[i].t >= 0.0f;
    if (a[i].visible != b[i].visible) ++g.visibleDiffer;
    if (hitA != hitB) {
      ++g.hitMissDiffer;
      continue;
    }
    if (!hitA) continue;
    ++g.hits;
    if (!closeT(a[i].t, b[i].t, scale[i]))
      ++g.tDiffer;
    else if (a[i].instance != b[i].instance || a[i].triangle != b[i].triangle || a[i].geometry != b[i].geometry)
      ++g.tieDiffer;
  }
  return g;
}

std::vector<gpu::TraceBatchResult> embreeResults(const engine::CpuTracer& tracer,
                                                 const std::vector<gpu::TraceBatchRay>& rays) {
  std::vector<gpu::TraceBatchResult> out;
  for (const gpu::TraceBatchRay& r : rays) {
    engine::CpuHit hit = engine::cpuTraceClosest(tracer, r.origin, r.direction, r.tMin, r.tMax);
    gpu::TraceBatchResult res{};
    res.t = hit.t;
    res.instance = hit.instance;
    res.geometry = hit.geometry;
    res.triangle = hit.triangle;
    res.barycentrics = hit.barycentrics;
    res.visible = engine::cpuTraceVisible(tracer, r.origin, r.direction, r.tMin, r.tMax) ? 1u : 0u;
    out.push_back(res);
  }
  return out;
}

// Rays that graze an edge or a corner may pass between two triangles in one
// traversal and not in another (the three differ in watertightness), and rays
// through a shared edge may report either triangle: a few per thousand.
void expectAgree(const Agreement& g, const char* what) {
  SCOPED_TRACE(what);
  std::printf("%s: %zu rays, %zu hits; differ: hit/miss %zu, t %zu, tie %zu, visibility %zu\n", what, g.rays, g.hits,
              g.hitMissDiffer, g.tDiffer, g.tieDiffer, g.visibleDiffer);
  ASSERT_GT(g.rays, 0u);
  EXPECT_GT(g.hits, g.rays / 4) << "too few hits for the comparison to mean anything";
  EXPECT_LE(double(g.hitMissDiffer), 0.002 * double(g.rays))
      << g.hitMissDiffer << " of " << g.rays << " rays hit in one only";
  EXPECT_LE(double(g.tDiffer), 0.002 * double(g.rays))
      << g.tDiffer << " of " << g.hits << " hits differ in t beyond 1e-5";
  EXPECT_LE(double(g.tieDiffer), 0.01 * double(g.rays)) << g.tieDiffer << " hits at equal t name another triangle";
  EXPECT_LE(double(g.visibleDiffer), 0.002 * double(g.rays)) << g.visibleDiffer << " rays differ in visibility";
}

}  // namespace

class TraversalTest : public GpuTest {
 protected:
  // Compares compute with ray queries (where the device has them) and with Embree; a scene for ray queries
  // alone (`compute` false): ray queries with Embree.
  void checkScene(const engine::Scene& scene, const engine::SceneGpu& gpu, uint32_t w = 64, uint32_t h = 48,
                  bool compute = true) {
    std::string tracerError;
    engine::CpuTracerPtr tracer = engine::createCpuTracer(scene, tracerError);
    ASSERT_TRUE(tracer) << tracerError;
    std::vector<gpu::TraceBatchRay> rays = makeRays(scene, *tracer, w, h);
    if (!compute) {
      std::vector<gpu::TraceBatchResult> rayQuery = oracle::traceBatch(ctx, gpu, gpu::TRAVERSAL_RAY_QUERY, rays);
      expectAgree(compare(rayQuery, embreeResults(*tracer, rays), rays), "ray queries vs Embree");
      return;
    }
    std::vector<gpu::TraceBatchResult> computeResults = oracle::traceBatch(ctx, gpu, gpu::TRAVERSAL_COMPUTE, rays);
    expectAgree(compare(computeResults, embreeResults(*tracer, rays), rays), "compute vs Embree");
    if (ctx.rayQuery) {
      std::vector<gpu::TraceBatchResult> rayQuery = oracle::traceBatch(ctx, gpu, gpu::TRAVERSAL_RAY_QUERY, rays);
      expectAgree(compare(computeResults, rayQuery, rays), "compute vs ray queries");
    }
  }
  // Loads with both traversals' structures: the tests compare them.
  static void loadBoth(const std::string& path, LoadedScene& s) {
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, s.scene, error)) << error;
    s.scene.bothTraversals = true;
    s.upload(ctx);
  }
  void checkFile(const std::string& path) {
    LoadedScene s;
    ASSERT_NO_FATAL_FAILURE(loadBoth(path, s));
    checkScene(s.scene, s.gpu);
  }
};

TEST_F(TraversalTest, CornellBoxAgrees) { checkFile(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf")); }
TEST_F(TraversalTest, SponzaAgrees) { checkFile(sharedScene("sponza-dabrovic/sponza-dabrovic.gltf")); }
TEST_F(TraversalTest, ConferenceAgrees) { checkFile(sharedScene("conference-ward/conference-ward.gltf")); }

// The box instances of cornell-simple are static, so they sit in the merged
// level; moving them must take them out of it.
TEST_F(TraversalTest, MovedInstancesAgree) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(loadBoth(sharedScene("cornell-simple/cornell_simple.gltf"), s));
  uint32_t boxMesh = s.scene.instances.back().mesh;
  for (engine::Instance& inst : s.scene.instances)
    if (inst.mesh == boxMesh)
      inst.worldFromObject = glm::rotate(glm::translate(inst.worldFromObject, {0.2f, 0.0f, 0.1f}), 0.3f, {0, 1, 0});
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordUpdateOrFail(ctx, cmd, s.scene, s.gpu); });
  checkScene(s.scene, s.gpu);
  // Moving again only rebuilds the top level.
  for (engine::Instance& inst : s.scene.instances)
    if (inst.mesh == boxMesh) inst.worldFromObject = glm::translate(inst.worldFromObject, {-0.1f, 0.05f, 0.0f});
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordUpdateOrFail(ctx, cmd, s.scene, s.gpu); });
  checkScene(s.scene, s.gpu);
}

namespace {

// Mesh `mesh`'s vertices twisted about its vertical axis, by `turns` radians from its bottom to its top
// (normals turned with their vertices), from the rest pose `rest` (positions, then normals).
void twistMesh(engine::Scene& scene, uint32_t mesh, const std::vector<glm::vec3>& restPositions,
               const std::vector<glm::vec3>& restNormals, float turns) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  const engine::Mesh& m = scene.meshes[mesh];
  auto forEachVertex = [&](auto&& f) {
    for (uint32_t p = m.firstPrimitive; p < m.firstPrimitive + m.primitiveCount; ++p)
      for (uint32_t v = scene.primitives[p].vertexOffset;
           v < scene.primitives[p].vertexOffset + scene.primitives[p].vertexCount; ++v)
        f(v);
  };
  forEachVertex([&](uint32_t v) {
    lo = glm::min(lo, restPositions[v]);
    hi = glm::max(hi, restPositions[v]);
  });
  const glm::vec3 centre = 0.5f * (lo + hi);
  forEachVertex([&](uint32_t v) {
    const float angle = turns * (restPositions[v].y - lo.y) / std::max(hi.y - lo.y, 1e-6f);
    const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), angle, {0, 1, 0}));
    scene.positions[v] = centre + turn * (restPositions[v] - centre);
    scene.normals[v] = turn * restNormals[v];
  });
}

}  // namespace

// A deformable mesh (gi::MeshDesc::deformable) twisted on the CPU and handed over (gi::updateMeshVertices):
// the BVH refit on the device, and with ray queries the updated BLAS, trace ray by ray as Embree's BVH
// built from scratch on the twisted mesh. The same vertices from device buffers (the device-stream path a
// skinning pass would take) give the same hits as the CPU arrays, and a scene created from the twisted mesh
// renders the same reference image.
TEST_F(TraversalTest, DeformedMeshesAgree) {
  LoadedScene s;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-simple/cornell_simple.gltf"), s.scene, error))
      << error;
  const uint32_t boxMesh = s.scene.instances.back().mesh;
  s.scene.meshes[boxMesh].deformable = true;
  s.scene.bothTraversals = true;
  s.scene.rebuildCostRatio = 0.0f;  // refits only: the arrays and the streams then trace one tree
  s.upload(ctx);
  const std::vector<glm::vec3> restPositions = s.scene.positions, restNormals = s.scene.normals;
  for (float turns : {0.5f, 1.2f}) {
    SCOPED_TRACE(turns);
    twistMesh(s.scene, boxMesh, restPositions, restNormals, turns);
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      std::string e;
      EXPECT_TRUE(engine::recordMeshVertexUpdate(cmd, s.scene, s.gpu, boxMesh, e)) << e;
    });
    checkScene(s.scene, s.gpu);
  }
  std::string tracerError;
  engine::CpuTracerPtr tracer = engine::createCpuTracer(s.scene, tracerError);
  ASSERT_TRUE(tracer) << tracerError;
  const std::vector<gpu::TraceBatchRay> rays = makeRays(s.scene, *tracer, 32, 24);
  const std::vector<gpu::TraceBatchResult> fromArrays = oracle::traceBatch(ctx, s.gpu, gpu::TRAVERSAL_COMPUTE, rays);

  // The same vertices from device buffers, after a different pose in between.
  twistMesh(s.scene, boxMesh, restPositions, restNormals, -0.3f);
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    std::string e;
    EXPECT_TRUE(engine::recordMeshVertexUpdate(cmd, s.scene, s.gpu, boxMesh, e)) << e;
  });
  twistMesh(s.scene, boxMesh, restPositions, restNormals, 1.2f);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  engine::Buffer positions = engine::createBufferFrom(ctx, std::span<const glm::vec3>(s.scene.positions), usage, error);
  engine::Buffer normals = engine::createBufferFrom(ctx, std::span<const glm::vec3>(s.scene.normals), usage, error);
  ASSERT_EQ(error, "");
  gi::MeshVertices streams;
  streams.devicePositions = {positions.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
  streams.deviceNormals = {normals.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
  submitOrFail(ctx,
               [&](VkCommandBuffer cmd) { ASSERT_FALSE(gi::updateMeshVertices(s.gpu.scene, cmd, boxMesh, streams)); });
  const std::vector<gpu::TraceBatchResult> fromStreams = oracle::traceBatch(ctx, s.gpu, gpu::TRAVERSAL_COMPUTE, rays);
  ASSERT_EQ(fromStreams.size(), fromArrays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(fromStreams[i].t, fromArrays[i].t) << "ray " << i;
    EXPECT_EQ(fromStreams[i].triangle, fromArrays[i].triangle) << "ray " << i;
    EXPECT_EQ(fromStreams[i].visible, fromArrays[i].visible) << "ray " << i;
  }
  engine::destroyBuffer(ctx, positions);
  engine::destroyBuffer(ctx, normals);

  // A scene built from scratch on the twisted mesh: the same reference image, to the sums' rounding.
  LoadedScene fresh;
  fresh.scene = s.scene;
  fresh.scene.meshes[boxMesh].deformable = false;
  fresh.scene.bothTraversals = true;
  fresh.upload(ctx);
  engine::ReferenceSettings settings;
  settings.maxBounces = 2;
  const engine::ReferenceImages refit = render(s, 32, 32, settings, 16), rebuilt = render(fresh, 32, 32, settings, 16);
  double difference = 0.0, sum = 0.0;
  for (size_t i = 0; i < refit.final.pixels.size(); ++i) {
    difference += std::abs(double(refit.final.pixels[i]) - rebuilt.final.pixels[i]);
    sum += std::abs(double(rebuilt.final.pixels[i]));
  }
  std::printf("twisted box, refit against rebuilt: reference images' relative L1 %.2e\n", difference / sum);
  EXPECT_GT(sum, 0.0);
  EXPECT_LT(difference / sum, 1e-3);
}

namespace {

// Cornell (simple) with a deformable 40×40 grid (3,200 triangles) across its middle, for both traversals,
// and the grid's updates: folded like an accordion by `amount` (tools/deformed_grid.h), rippled by `ripple`.
struct FoldedGrid {
  LoadedScene s;
  uint32_t grid = 0;
  std::vector<glm::vec3> rest;

  // `both`: with both traversals' structures (else the context's traversal alone).
  void load(const engine::Context& ctx, float rebuildCostRatio, bool rebuildOffThread, bool both = true) {
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-simple/cornell_simple.gltf"), s.scene, error))
        << error;
    const engine::Bounds bounds = s.scene.worldBounds();
    grid = tools::appendGrid(s.scene, 40, 0.5f * (bounds.min + bounds.max), 0.5f * bounds.extent());
    s.scene.bothTraversals = both;
    s.scene.rebuildCostRatio = rebuildCostRatio;
    s.scene.rebuildOffThread = rebuildOffThread;
    s.upload(ctx);
    rest = s.scene.positions;
  }
  gi::SceneInfo update(const engine::Context& ctx, float amount, float ripple) {
    tools::foldGrid(s.scene, grid, rest, 8, amount, ripple);
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      std::string e;
      EXPECT_TRUE(engine::recordMeshVertexUpdate(cmd, s.scene, s.gpu, grid, e)) << e;
    });
    return gi::sceneInfo(s.gpu.scene);
  }
  // The same pose handed over as device streams (the scene's whole vertex arrays in two device buffers).
  gi::SceneInfo updateFromDevice(const engine::Context& ctx, float amount, float ripple) {
    tools::foldGrid(s.scene, grid, rest, 8, amount, ripple);
    std::string error;
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    engine::Buffer positions =
        engine::createBufferFrom(ctx, std::span<const glm::vec3>(s.scene.positions), usage, error);
    engine::Buffer normals = engine::createBufferFrom(ctx, std::span<const glm::vec3>(s.scene.normals), usage, error);
    EXPECT_TRUE(error.empty()) << error;
    gi::MeshVertices streams;
    streams.devicePositions = {positions.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
    streams.deviceNormals = {normals.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
    submitOrFail(ctx,
                 [&](VkCommandBuffer cmd) { EXPECT_FALSE(gi::updateMeshVertices(s.gpu.scene, cmd, grid, streams)); });
    engine::destroyBuffer(ctx, positions);
    engine::destroyBuffer(ctx, normals);
    return gi::sceneInfo(s.gpu.scene);
  }
};

}  // namespace

// SceneCreateDesc::rebuildCostRatio: a grid rippled with CPU arrays keeps its level (refit; its cost as
// built, to a few per cent), the same grid folded like an accordion degrades its refit level past the
// ratio and is rebuilt on the CPU (with ray queries its BLAS built anew), and after the rebuild and a
// refit that follows it the compute traversal traces as ray queries and Embree do; with the ratio 0 the
// fold is only refit, at a cost many times the built one. A ratio that is not finite is a named error.
TEST_F(TraversalTest, DegradedRefitsAreRebuiltAndTraceAsBuiltFromScratch) {
  {
    LoadedScene bad;
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-simple/cornell_simple.gltf"), bad.scene, error));
    bad.scene.rebuildCostRatio = INFINITY;
    engine::SceneGpu gpu;
    EXPECT_FALSE(engine::createSceneGpu(ctx, bad.scene, gpu, error));
    EXPECT_NE(error.find("desc.rebuildCostRatio = inf is not a finite ratio"), std::string::npos) << error;
    engine::destroySceneGpu(ctx, gpu);
  }
  for (float ratio : {1.5f, 0.0f}) {
    SCOPED_TRACE(ratio);
    FoldedGrid folding;
    folding.load(ctx, ratio, false);  // the update that finds the level degraded rebuilds it
    auto update = [&](float amount, float ripple) { return folding.update(ctx, amount, ripple); };
    const engine::Scene& scene = folding.s.scene;
    const engine::SceneGpu& gpu = folding.s.gpu;
    const gi::SceneInfo rippled = update(0.0f, 0.002f);
    std::printf("rebuildCostRatio %.1f: rippled, cost ratio %.3f, rebuilds %u\n", ratio, rippled.refitCostRatio,
                rippled.levelRebuilds);
    EXPECT_LT(rippled.refitCostRatio, 1.1f);
    EXPECT_EQ(rippled.levelRebuilds, 0u);
    const gi::SceneInfo folded = update(1.0f, 0.0f);
    std::printf("rebuildCostRatio %.1f: folded, cost ratio %.3f, rebuilds %u\n", ratio, folded.refitCostRatio,
                folded.levelRebuilds);
    if (ratio > 0.0f) {
      EXPECT_EQ(folded.levelRebuilds, 1u);
      EXPECT_EQ(folded.refitCostRatio, 1.0f);  // the level as just built
    } else {
      EXPECT_EQ(folded.levelRebuilds, 0u);
      EXPECT_GT(folded.refitCostRatio, 3.0f);
    }
    checkScene(scene, gpu);
    // A refit of the rebuilt level (or the degraded one) still traces exactly.
    const gi::SceneInfo after = update(1.0f, 0.001f);
    EXPECT_EQ(after.levelRebuilds, folded.levelRebuilds);
    checkScene(scene, gpu);
  }
}

// The same fold with the rebuild on the module's worker thread (the default): the update that finds the
// level degraded starts it and refits meanwhile, so its ratio stays the degraded one; a later update of the
// mesh installs the level built from the folded pose, which then traces as ray queries and Embree do, in
// that pose and in a pose moved on from it before the install (refit to it).
TEST_F(TraversalTest, OffThreadRebuildsAreInstalledByALaterUpdate) {
  FoldedGrid folding;
  folding.load(ctx, 1.5f, true);
  auto update = [&](float amount, float ripple) { return folding.update(ctx, amount, ripple); };
  const engine::Scene& scene = folding.s.scene;
  const engine::SceneGpu& gpu = folding.s.gpu;
  const gi::SceneInfo folded = update(1.0f, 0.0f);
  EXPECT_EQ(folded.levelRebuilds, 0u) << "started, not waited for";
  EXPECT_GT(folded.refitCostRatio, 1.5f);
  checkScene(scene, gpu);  // refit meanwhile: exact
  // A little later the rebuild has finished: the next update installs it (3,200 triangles build in
  // milliseconds; the loop allows 20 s).
  gi::SceneInfo installed = folded;
  for (int i = 0; i < 2000 && installed.levelRebuilds == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    installed = update(1.0f, 0.001f * float(i % 2));
  }
  std::printf("off thread: folded, cost ratio %.3f; installed after the fold with ratio %.3f\n", folded.refitCostRatio,
              installed.refitCostRatio);
  EXPECT_EQ(installed.levelRebuilds, 1u);
  EXPECT_EQ(installed.refitCostRatio, 1.0f);  // measured as installed
  checkScene(scene, gpu);
  const gi::SceneInfo after = update(1.0f, 0.002f);
  EXPECT_EQ(after.levelRebuilds, 1u);
  EXPECT_LT(after.refitCostRatio, 1.1f);
  checkScene(scene, gpu);
}

// Device streams (an engine's skinning) are measured too, on positions read back without a wait: the
// update that folds the grid copies them behind an event, a later one takes them, finds the level degraded
// and starts its rebuild, and a later one still installs it; the level then traces exactly, in the folded
// pose and refit to a ripple handed over after it, whose read-back measure finds it near its built cost.
TEST_F(TraversalTest, DeviceStreamLevelsAreMeasuredOnReadBackPositions) {
  FoldedGrid folding;
  folding.load(ctx, 1.5f, true);
  gi::SceneInfo info = folding.updateFromDevice(ctx, 1.0f, 0.0f);
  EXPECT_EQ(info.levelRebuilds, 0u) << "its positions are on their way";
  float worst = info.refitCostRatio;
  int updates = 1;
  for (; updates < 2000 && info.levelRebuilds == 0; ++updates) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    info = folding.updateFromDevice(ctx, 1.0f, 0.0f);
    if (info.levelRebuilds == 0) worst = std::max(worst, info.refitCostRatio);
  }
  std::printf("device streams: the fold measured at %.3f of its built cost, rebuilt at update %d\n", worst, updates);
  EXPECT_GT(worst, 1.5f);
  EXPECT_EQ(info.levelRebuilds, 1u);
  checkScene(folding.s.scene, folding.s.gpu);
  for (int i = 0; i < 3; ++i) info = folding.updateFromDevice(ctx, 1.0f, 0.002f);
  EXPECT_EQ(info.levelRebuilds, 1u);
  EXPECT_LT(info.refitCostRatio, 1.1f);
  checkScene(folding.s.scene, folding.s.gpu);
}

// A scene for ray queries alone has no compute BVH to trace, yet keeps its deformable meshes' levels on
// the CPU (never uploaded) for the measure that tells when their BLAS is built anew: a ripple measures
// near its built cost; the fold measures past the ratio and is rebuilt in that update, its BLAS built
// anew, and traces as Embree does, also after a further refit; with the ratio 0 the fold is measured
// (several times its built cost) and only updated.
TEST_F(TraversalTest, RayQueryScenesMeasureTheirDeformableLevelsToo) {
  if (ctx.traversal != engine::Traversal::RayQuery) GTEST_SKIP() << "the ray-query variant runs it";
  for (float ratio : {1.5f, 0.0f}) {
    SCOPED_TRACE(ratio);
    FoldedGrid folding;
    folding.load(ctx, ratio, false, false);
    ASSERT_FALSE(gi::sceneDesc(folding.s.gpu.scene).hasComputeBvh);
    const gi::SceneInfo rippled = folding.update(ctx, 0.0f, 0.002f);
    EXPECT_GT(rippled.refitCostRatio, 0.5f) << "measured (0: not)";
    EXPECT_LT(rippled.refitCostRatio, 1.1f);
    EXPECT_EQ(rippled.levelRebuilds, 0u);
    const gi::SceneInfo folded = folding.update(ctx, 1.0f, 0.0f);
    std::printf("ray queries alone, rebuildCostRatio %.1f: folded, cost ratio %.3f, rebuilds %u\n", ratio,
                folded.refitCostRatio, folded.levelRebuilds);
    EXPECT_EQ(folded.levelRebuilds, ratio > 0.0f ? 1u : 0u);
    if (ratio > 0.0f)
      EXPECT_EQ(folded.refitCostRatio, 1.0f);
    else
      EXPECT_GT(folded.refitCostRatio, 3.0f);
    checkScene(folding.s.scene, folding.s.gpu, 64, 48, false);
    const gi::SceneInfo after = folding.update(ctx, 1.0f, 0.001f);
    EXPECT_EQ(after.levelRebuilds, folded.levelRebuilds);
    checkScene(folding.s.scene, folding.s.gpu, 64, 48, false);
  }
}

// What gi::updateMeshVertices refuses, by name: a mesh not created deformable, a mesh index past the
// scene's, a vertex that is not finite, arrays and streams together.
TEST_F(TraversalTest, MeshVertexUpdatesNameWhatIsWrong) {
  LoadedScene s;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-simple/cornell_simple.gltf"), s.scene, error))
      << error;
  const uint32_t boxMesh = s.scene.instances.back().mesh, otherMesh = s.scene.instances.front().mesh;
  ASSERT_NE(boxMesh, otherMesh);
  s.scene.meshes[boxMesh].deformable = true;
  s.scene.bothTraversals = true;
  s.upload(ctx);
  std::vector<glm::vec3> positions = s.scene.positions;
  gi::MeshVertices v;
  v.positions = &positions[0].x;
  v.normals = &s.scene.normals[0].x;
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    EXPECT_NE(gi::updateMeshVertices(s.gpu.scene, cmd, otherMesh, v).message.find("was not created deformable"),
              std::string::npos);
    EXPECT_NE(gi::updateMeshVertices(s.gpu.scene, cmd, 1000, v).message.find("is not below the scene's"),
              std::string::npos);
    const engine::Primitive& p = s.scene.primitives[s.scene.meshes[boxMesh].firstPrimitive];
    positions[p.vertexOffset + 1].y = std::nanf("");
    EXPECT_NE(gi::updateMeshVertices(s.gpu.scene, cmd, boxMesh, v)
                  .message.find("positions[" + std::to_string(p.vertexOffset + 1) + "] is not finite"),
              std::string::npos);
    v.devicePositions.address = 256;
    EXPECT_NE(gi::updateMeshVertices(s.gpu.scene, cmd, boxMesh, v).message.find("both given"), std::string::npos);
    EXPECT_NE(
        gi::holdMeshVertices(s.gpu.scene, cmd, otherMesh)
            .message.find("gi::holdMeshVertices: mesh " + std::to_string(otherMesh) + " was not created deformable"),
        std::string::npos);
    EXPECT_NE(gi::holdMeshVertices(s.gpu.scene, cmd, 1000).message.find("is not below the scene's"), std::string::npos);
    EXPECT_NE(gi::holdMeshVertices(s.gpu.scene, VK_NULL_HANDLE, boxMesh).message.find("cmd is VK_NULL_HANDLE"),
              std::string::npos);
    EXPECT_FALSE(gi::holdMeshVertices(s.gpu.scene, cmd, boxMesh));
  });
}

namespace {

// Two quads facing the camera: a front one whose material is alpha-masked,
// and a back one. `frontAlpha` below the cutoff (0.5) makes the front a hole.
engine::Scene maskedQuads(float frontAlpha) {
  engine::Scene scene;
  auto quad = [&](float z, uint32_t material) {
    uint32_t base = uint32_t(scene.positions.size());
    for (glm::vec3 p : {glm::vec3(-1, -1, z), glm::vec3(1, -1, z), glm::vec3(1, 1, z), glm::vec3(-1, 1, z)}) {
      scene.positions.push_back(p);
      scene.normals.push_back({0, 0, 1});
      scene.uvs.push_back({0, 0});
    }
    uint32_t first = uint32_t(scene.indices.size());
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) scene.indices.push_back(i);
    scene.primitives.push_back({first, 6, base, 4, material});
    uint32_t mesh = uint32_t(scene.meshes.size());
    scene.meshes.push_back({"quad", uint32_t(scene.primitives.size() - 1), 1});
    scene.instances.push_back({"quad", mesh, glm::mat4(1.0f)});
  };
  engine::Material front, back;
  front.alphaMode = engine::AlphaMode::Mask;
  front.baseColor = {0.5f, 0.5f, 0.5f, frontAlpha};
  scene.materials = {front, back};
  quad(0.0f, 0);
  quad(-1.0f, 1);
  engine::Camera cam;
  cam.worldFromView = glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, 3.0f});
  cam.yfov = 0.5f;
  scene.cameras = {cam};
  return scene;
}

}  // namespace

TEST_F(TraversalTest, AlphaMaskedGeometryIsAHoleOnlyBelowTheCutoff) {
  for (float alpha : {0.25f, 0.75f}) {
    SCOPED_TRACE(alpha);
    engine::Scene scene = maskedQuads(alpha);
    engine::SceneGpu gpu;
    scene.bothTraversals = true;
    std::string sceneError;
    ASSERT_TRUE(engine::createSceneGpu(ctx, scene, gpu, sceneError)) << sceneError;
    ASSERT_TRUE(gpu.desc.hasAlphaMask);
    std::vector<gpu::TraceBatchRay> rays;
    for (int i = 0; i < 64; ++i)
      rays.push_back({{0.02f * float(i % 8) - 0.07f, 0.02f * float(i / 8) - 0.07f, 3.0f}, 0.0f, {0, 0, -1}, 1e30f});
    std::vector<uint32_t> traversals = {gpu::TRAVERSAL_COMPUTE};
    if (ctx.rayQuery) traversals.push_back(gpu::TRAVERSAL_RAY_QUERY);
    for (uint32_t traversal : traversals) {
      std::vector<gpu::TraceBatchResult> hits = oracle::traceBatch(ctx, gpu, traversal, rays);
      for (const gpu::TraceBatchResult& h : hits) {
        EXPECT_EQ(h.instance, alpha < 0.5f ? 1u : 0u) << "traversal " << traversal;
        EXPECT_NEAR(h.t, alpha < 0.5f ? 4.0f : 3.0f, 1e-5f);
        EXPECT_EQ(h.visible, 0u);
      }
    }
    engine::destroySceneGpu(ctx, gpu);
  }
}

namespace {

// The Cornell box scaled by `scale` (vertices and camera), with degenerate
// triangles added across the view when `degenerate`.
engine::Scene scaledCornell(const engine::Scene& source, float scale, bool degenerate) {
  engine::Scene scene = source;
  for (glm::vec3& p : scene.positions) p *= scale;
  for (engine::Instance& inst : scene.instances)
    inst.worldFromObject[3] = glm::vec4(glm::vec3(inst.worldFromObject[3]) * scale, 1.0f);
  for (engine::Camera& c : scene.cameras) c.worldFromView[3] = glm::vec4(glm::vec3(c.worldFromView[3]) * scale, 1.0f);
  if (degenerate) {
    engine::Bounds b = scene.worldBounds();
    glm::vec3 c = b.center();
    uint32_t base = uint32_t(scene.positions.size()), first = uint32_t(scene.indices.size());
    // A zero-area sliver (three collinear points) and a point triangle.
    for (glm::vec3 p : {b.min, c, b.max, c, c, c}) {
      scene.positions.push_back(p);
      scene.normals.push_back({0, 1, 0});
      scene.uvs.push_back({0, 0});
    }
    for (uint32_t i = 0; i < 6; ++i) scene.indices.push_back(i);
    scene.primitives.push_back({first, 6, base, 6, 0});
    scene.meshes.push_back({"degenerate", uint32_t(scene.primitives.size() - 1), 1});
    scene.instances.push_back({"degenerate", uint32_t(scene.meshes.size() - 1), glm::mat4(1.0f)});
  }
  return scene;
}

}  // namespace

TEST_F(TraversalTest, ExtremeScalesAndDegenerateTrianglesAgree) {
  engine::Scene cornell;
  std::string error;
  ASSERT_TRUE(
      engine::loadSceneForRendering(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), cornell, error))
      << error;
  for (auto [scale, degenerate] : {std::pair{1e-3f, false}, std::pair{1e5f, false}, std::pair{1.0f, true}}) {
    SCOPED_TRACE(scale);
    engine::Scene scene = scaledCornell(cornell, scale, degenerate);
    engine::SceneGpu gpu;
    scene.bothTraversals = true;
    std::string sceneError;
    ASSERT_TRUE(engine::createSceneGpu(ctx, scene, gpu, sceneError)) << sceneError;
    checkScene(scene, gpu);
    if (degenerate) {  // nothing ever reports the degenerate triangles
      std::string tracerError;
      engine::CpuTracerPtr tracer = engine::createCpuTracer(scene, tracerError);
      ASSERT_TRUE(tracer) << tracerError;
      std::vector<gpu::TraceBatchRay> rays = makeRays(scene, *tracer, 32, 24);
      uint32_t degenerateInstance = uint32_t(scene.instances.size() - 1);
      for (const gpu::TraceBatchResult& r : oracle::traceBatch(ctx, gpu, gpu::TRAVERSAL_COMPUTE, rays))
        if (r.t >= 0.0f) {
          EXPECT_NE(r.instance, degenerateInstance);
        }
    }
    engine::destroySceneGpu(ctx, gpu);
  }
}

// The BVH the compute backend walks is Embree's SAH tree in our node format:
// every triangle is in some leaf (spatial splits may put one in several),
// every leaf entry is reached once, and every triangle overlaps the box of
// each node on its way down (a split triangle's boxes hold only its part).
TEST(BvhBuilder, EveryTriangleOnceAndChildBoxesEncloseTheirSubtrees) {
  engine::Scene scene;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), scene, error))
      << error;
  std::vector<gi::BvhMesh> meshes(scene.meshes.size());
  size_t triangles = 0;
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    for (uint32_t p = 0; p < scene.meshes[m].primitiveCount; ++p) {
      const engine::Primitive& prim = scene.primitives[scene.meshes[m].firstPrimitive + p];
      meshes[m].geometries.push_back(
          {prim.firstIndex, prim.indexCount / 3, prim.vertexOffset, scene.meshes[m].firstPrimitive + p});
    }
  std::vector<gi::BvhInstance> instances;
  for (const engine::Instance& inst : scene.instances) {
    instances.push_back({inst.mesh, inst.worldFromObject, false});
    for (uint32_t p = 0; p < scene.meshes[inst.mesh].primitiveCount; ++p)
      triangles += scene.primitives[scene.meshes[inst.mesh].firstPrimitive + p].indexCount / 3;
  }
  instances.back().movable = true;  // one instance keeps its own level
  const uint32_t own = scene.instances.back().mesh;
  meshes[own].deformable = true;  // refit in place: no split fragments, room for a rebuild
  gi::SceneBvh bvh = gi::buildSceneBvh({scene.positions, scene.indices, meshes, instances});
  std::vector<int> seen(bvh.triangles.size(), 0);
  std::set<std::tuple<uint32_t, uint32_t, uint32_t>> found;  // (geometry, triangle, instance) reached
  // Walks a subtree, checking that every triangle lies inside the box its parent gave it.
  std::function<void(uint32_t, glm::vec3, glm::vec3)> walk = [&](uint32_t ref, glm::vec3 lo, glm::vec3 hi) {
    if (ref == gpu::BVH_NO_CHILD) return;
    if (ref & gpu::BVH_LEAF_BIT) {
      uint32_t first = ref & gpu::BVH_LEAF_FIRST_MASK, count = ((ref >> gpu::BVH_LEAF_COUNT_SHIFT) & 15u) + 1u;
      for (uint32_t i = first; i < first + count; ++i) {
        ASSERT_LT(i, bvh.triangles.size());
        ++seen[i];
        const gpu::GpuBvhTriangle& t = bvh.triangles[i];
        glm::vec3 tLo = glm::min(t.v0, glm::min(t.v0 + t.edge1, t.v0 + t.edge2));
        glm::vec3 tHi = glm::max(t.v0, glm::max(t.v0 + t.edge1, t.v0 + t.edge2));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(tLo, hi + 1e-5f)) && glm::all(glm::greaterThanEqual(tHi, lo - 1e-5f)))
            << "triangle " << i << " outside its leaf's box";
        found.insert({t.geometry, t.triangle, t.instance});
      }
      return;
    }
    ASSERT_LT(ref, bvh.bottomNodes.size());
    const gpu::GpuBvhNode& n = bvh.bottomNodes[ref];
    for (uint32_t c = 0; c < gpu::BVH_WIDTH; ++c)
      walk(n.child[c], {n.minX[c], n.minY[c], n.minZ[c]}, {n.maxX[c], n.maxY[c], n.maxZ[c]});
  };
  walk(bvh.mergedRoot, glm::vec3(-1e30f), glm::vec3(1e30f));
  walk(bvh.meshRoot[scene.instances.back().mesh], glm::vec3(-1e30f), glm::vec3(1e30f));
  size_t movableTriangles = 0;
  for (uint32_t p = 0; p < scene.meshes[scene.instances.back().mesh].primitiveCount; ++p)
    movableTriangles += scene.primitives[scene.meshes[scene.instances.back().mesh].firstPrimitive + p].indexCount / 3;
  EXPECT_EQ(found.size(), triangles);  // every instanced triangle, once per (instance, triangle)
  EXPECT_GE(bvh.triangles.size(), triangles);
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "triangle " << i;
  EXPECT_GT(movableTriangles, 0u);
  EXPECT_EQ(bvh.topInstances.size(), 2u);  // the merged level and the movable instance

  // The deformable level: one slot a triangle; rebuilt in a sheared pose (rebuildMeshLevel) it keeps its
  // root and slots, holds each triangle once inside its boxes, and costs no more than the old tree refit
  // to that pose (meshLevelCost, which counts the root's own area: at least 1).
  EXPECT_EQ(bvh.meshTriangleCount[own], movableTriangles) << "a deformable level holds no split fragments";
  EXPECT_GE(gi::meshLevelCost({scene.positions, scene.indices, meshes, instances}, bvh, own), 1.0);
  std::vector<glm::vec3> sheared = scene.positions;
  for (glm::vec3& v : sheared) v.x += 3.0f * std::sin(7.0f * v.z);
  const gi::BvhInput input{sheared, scene.indices, meshes, instances};
  const double refitCost = gi::meshLevelCost(input, bvh, own);
  const uint32_t root = bvh.meshRoot[own], first = bvh.meshFirstTriangle[own];
  ASSERT_TRUE(gi::rebuildMeshLevel(input, own, bvh));
  EXPECT_EQ(bvh.meshRoot[own], root);
  EXPECT_EQ(bvh.meshFirstTriangle[own], first);
  EXPECT_LE(gi::meshLevelCost(input, bvh, own), refitCost);
  std::fill(seen.begin(), seen.end(), 0);
  walk(root, glm::vec3(-1e30f), glm::vec3(1e30f));
  for (uint32_t i = first; i < first + bvh.meshTriangleCount[own]; ++i) EXPECT_EQ(seen[i], 1) << "triangle " << i;
}

// A large level's cost kept in parts (meshLevelCostInParts, what updates of more than 64k triangles use):
// the first call measures every part and gives meshLevelCost; after a new pose, one part a call (a budget
// of one triangle) gives the new pose's cost once every part has been measured again.
TEST(BvhBuilder, ALevelsCostKeptInPartsIsItsWholeCost) {
  engine::Scene scene;
  const uint32_t grid = tools::appendGrid(scene, 40, glm::vec3(0.0f), 1.0f);
  std::vector<gi::BvhMesh> meshes(1);
  meshes[0].geometries.push_back({0, uint32_t(scene.indices.size() / 3), 0, 0});
  meshes[0].deformable = true;
  const std::vector<gi::BvhInstance> instances{{grid, glm::mat4(1.0f), true}};
  gi::SceneBvh bvh = gi::buildSceneBvh({scene.positions, scene.indices, meshes, instances});
  gi::LevelCostParts parts;
  const double built = gi::meshLevelCost({scene.positions, scene.indices, meshes, instances}, bvh, 0);
  EXPECT_NEAR(gi::meshLevelCostInParts({scene.positions, scene.indices, meshes, instances}, bvh, 0, 1, parts), built,
              1e-9 * built);
  ASSERT_GT(parts.parts.size(), 8u);
  const std::vector<glm::vec3> rest = scene.positions;
  tools::foldGrid(scene, grid, rest, 8, 1.0f, 0.0f);
  const gi::BvhInput folded{scene.positions, scene.indices, meshes, instances};
  const double refit = gi::meshLevelCost(folded, bvh, 0);
  EXPECT_GT(refit, 3.0 * built);
  double partly = 0.0;
  for (size_t i = 0; i < parts.parts.size(); ++i) {
    partly = gi::meshLevelCostInParts(folded, bvh, 0, 1, parts);
    if (i + 1 < parts.parts.size()) {
      EXPECT_LT(partly, refit) << "part " << i << ": some parts still as built";
    }
  }
  EXPECT_NEAR(partly, refit, 1e-9 * refit);
}

// A level rebuilt off the update's thread comes prepared (prepareMeshLevel: built, its cost walked once in
// the pose it was built from, its refit order derived) so the update that installs it only copies: its
// cost is the installed level's in that pose, and its refit order spliced into the plan
// (replaceMeshRefit) is the plan derived anew from the whole BVH, for the first of two levels (the second
// one's runs move) and for the second.
TEST(BvhBuilder, APreparedLevelInstallsAsTheLevelRebuiltInPlace) {
  engine::Scene scene;
  const uint32_t a = tools::appendGrid(scene, 24, glm::vec3(-2.0f, 0.0f, 0.0f), 1.0f);
  const uint32_t b = tools::appendGrid(scene, 16, glm::vec3(2.0f, 0.0f, 0.0f), 1.0f);
  std::vector<gi::BvhMesh> meshes(2);
  std::vector<gi::BvhInstance> instances;
  for (uint32_t m : {a, b}) {
    const engine::Primitive& p = scene.primitives[scene.meshes[m].firstPrimitive];
    meshes[m].geometries.push_back({p.firstIndex, p.indexCount / 3, p.vertexOffset, m});
    meshes[m].deformable = true;
    instances.push_back({m, glm::mat4(1.0f), true});
  }
  gi::SceneBvh bvh = gi::buildSceneBvh({scene.positions, scene.indices, meshes, instances});
  const std::vector<uint8_t> deformable{1, 1};
  gi::RefitPlan plan = gi::refitPlan(bvh, deformable);
  const std::vector<glm::vec3> rest = scene.positions;
  for (uint32_t m : {a, b}) {
    tools::foldGrid(scene, m, rest, 8, 1.0f, 0.0f);
    const gi::BvhInput folded{scene.positions, scene.indices, meshes, instances};
    gi::PreparedLevel prepared = gi::prepareMeshLevel(folded, m, gi::meshLevelSlots(bvh, m));
    ASSERT_FALSE(prepared.level.nodes.empty());
    gi::installMeshLevel(prepared.level, m, bvh);
    EXPECT_NEAR(prepared.cost, gi::meshLevelCost(folded, bvh, m), 1e-9 * prepared.cost) << "mesh " << m;
    const size_t changed = gi::replaceMeshRefit(plan, m, prepared.refit, prepared.order);
    const gi::RefitPlan fresh = gi::refitPlan(bvh, deformable);
    EXPECT_EQ(plan.order, fresh.order) << "mesh " << m;
    size_t runBefore = 0;  // the entries of the levels before m's, which the splice leaves as they were
    for (uint32_t k = 0; k < m; ++k)
      for (const auto& level : fresh.meshes[k].levels) runBefore += level.second;
    EXPECT_EQ(changed, runBefore) << "mesh " << m;
    for (uint32_t k : {a, b}) {
      EXPECT_EQ(plan.meshes[k].levels, fresh.meshes[k].levels) << "mesh " << m << ", level of " << k;
      EXPECT_EQ(plan.meshes[k].firstTriangle, fresh.meshes[k].firstTriangle);
      EXPECT_EQ(plan.meshes[k].triangleCount, fresh.meshes[k].triangleCount);
    }
  }
}
