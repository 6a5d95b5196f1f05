// gi-render end to end: named errors and exit codes for bad input, a
// validated render with its stats file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "run_process.h"

namespace {

const std::string kData = GI_TEST_DATA;
int runTool(const std::string& args, std::string& output) { return runProcess(GI_RENDER_BINARY, args, output); }

// gi-render with `args`, --traversal `traversal` and --stats into `dir`: its exit code, its output, whether
// the device refused ray queries (a device without them must), and the stats where it succeeded.
struct TraversalRun {
  int rc = 0;
  std::string out;
  bool refusedRayQueries = false;
  nlohmann::json stats;
};
TraversalRun runWithTraversal(const std::string& args, const char* traversal, const std::string& dir) {
  TraversalRun r;
  r.rc = runTool(args + " --validation --traversal " + traversal + " --stats " + dir + "/s.json", r.out);
  r.refusedRayQueries =
      std::string(traversal) == "rayquery" && r.out.find("does not support VK_KHR_ray_query") != std::string::npos;
  if (r.rc == 0) r.stats = nlohmann::json::parse(std::ifstream(dir + "/s.json"));
  return r;
}

}  // namespace

TEST(GiRenderTool, BadInputExitsWithASentence) {
  std::string out;
  EXPECT_EQ(runTool("--scene " + kData + "/malformed/index_out_of_range.gltf", out), 1) << out;
  EXPECT_NE(out.find("index_out_of_range.gltf: "), std::string::npos) << out;
  EXPECT_EQ(runTool("--scene /no/such.gltf", out), 1) << out;
  EXPECT_EQ(runTool("--bogus 1", out), 2) << out;
  EXPECT_NE(out.find("usage:"), std::string::npos);
  EXPECT_EQ(runTool("--scene x.gltf --size 0x10", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --spp -3", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --aov colour", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --method magic", out), 2) << out;
  EXPECT_EQ(runTool("--scene", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --sky 1,2", out), 2) << out;
  EXPECT_NE(out.find("--sky 1,2"), std::string::npos) << out;
  EXPECT_EQ(runTool("--scene x.gltf --sky /no/such_sky.exr", out), 2) << out;
  EXPECT_NE(out.find("such_sky.exr"), std::string::npos) << out;
  EXPECT_EQ(runTool("--scene x.gltf --light-sampler some", out), 2) << out;
  EXPECT_NE(out.find("--light-sampler must be all, power or tree, not 'some'"), std::string::npos) << out;
  EXPECT_EQ(runTool("--scene x.gltf --light-tree-cut 0", out), 2) << out;
  EXPECT_NE(out.find("--light-tree-cut"), std::string::npos) << out;
}

// --sky end to end, for the reference and a module method, with validation
// (its light is checked in tests/sky_test.cpp); the module's memory as --stats predicts it.
TEST(GiRenderTool, SkyRunsWithoutValidationMessages) {
  std::string dir = std::filesystem::temp_directory_path() / "gi_render_sky_test";
  std::filesystem::create_directories(dir);
  std::string out;
  for (const char* method : {"reference", "hpsf"}) {
    int rc = runTool("--scene " + std::string(GI_SHARED_SCENES) +
                         "/cornell-box-mcguire/CornellBox-Original.gltf --size 16x16 --spp 2 --validation --sky 2,2,2"
                         " --method " +
                         method + " --stats " + dir + "/s.json",
                     out);
    ASSERT_EQ(rc, 0) << out;
    std::ifstream f(dir + "/s.json");
    const nlohmann::json j = nlohmann::json::parse(f);
    EXPECT_EQ(j["validation_messages"], 0) << method;
    if (j.contains("module_memory_bytes")) {  // the module's figure after the frames, and its prediction before
      EXPECT_EQ(j["module_memory_predicted_bytes"], j["module_memory_bytes"]);
      EXPECT_EQ(j["module_memory_predicted_transient_bytes"], j["module_memory_transient_bytes"]);
    }
  }
}

TEST(GiRenderTool, RendersWithValidationAndWritesStats) {
  std::string dir = std::filesystem::temp_directory_path() / "gi_render_test";
  std::filesystem::create_directories(dir);
  std::string out;
  int rc = runTool("--scene " + std::string(GI_SHARED_SCENES) +
                       "/cornell-box-mcguire/CornellBox-Original.gltf --size 16x16 --spp 2 --max-bounces 2 --validation"
                       " --aov indirect --out " +
                       dir + "/i.pfm --stats " + dir + "/s.json",
                   out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/i.pfm"));
  std::ifstream f(dir + "/s.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["width"], 16);
  EXPECT_EQ(j["spp"], 2);
  EXPECT_EQ(j["max_bounces"], 2);
  EXPECT_GT(j["rays"].get<uint64_t>(), 16u * 16u * 2u);
  EXPECT_GT(j["passes_ms"]["path_trace"].get<double>(), 0.0);
  EXPECT_EQ(j["validation_messages"], 0);
  EXPECT_TRUE(j.contains("device"));
  EXPECT_TRUE(j.contains("wall_seconds"));
  EXPECT_TRUE(j["traversal"] == "compute" || j["traversal"] == "rayquery") << j["traversal"];
  EXPECT_EQ(j["scene_refit_cost_ratio"], 0.0) << "no deformable mesh to measure";
  EXPECT_EQ(j["scene_level_rebuilds"], 0);
}

// The skinned bar played under --animate: the engine poses it on the device and hands the module device
// streams, whose level the module measures on positions it reads back (the stats' cost ratio above 0:
// measured), with either traversal (a scene for ray queries alone keeps the level on the CPU for it).
TEST(GiRenderTool, AnimatedSkinsAreMeasuredForRebuilds) {
  std::string dir = std::filesystem::temp_directory_path() / "gi_render_test_skin";
  std::filesystem::create_directories(dir);
  for (const char* traversal : {"compute", "rayquery"}) {
    const TraversalRun run = runWithTraversal("--scene " + std::string(GI_ASSETS) +
                                                  "/skinned_bar/skinned_bar.gltf --method raw --animate --frames 24"
                                                  " --size 32x18 --out " +
                                                  dir + "/s.png",
                                              traversal, dir);
    if (run.refusedRayQueries) continue;  // the test below asserts the refusal
    ASSERT_EQ(run.rc, 0) << run.out;
    const nlohmann::json& j = run.stats;
    EXPECT_EQ(j["traversal"], traversal);
    EXPECT_GT(j["scene_refit_cost_ratio"].get<double>(), 0.0) << traversal << ": the bar's level was never measured";
    EXPECT_EQ(j["validation_messages"], 0);
  }
}

// A module method without --spp traces its own default (hpsf: 1 path per
// pixel), not the reference's 64; --traversal picks the backend the stats name. A device without ray
// queries (an H200's driver offers none) must refuse --traversal rayquery with a named error.
TEST(GiRenderTool, MethodsUseTheirOwnSamplesAndTheChosenTraversal) {
  std::string dir = std::filesystem::temp_directory_path() / "gi_render_test_method";
  std::filesystem::create_directories(dir);
  for (const char* traversal : {"compute", "rayquery"}) {
    const TraversalRun run = runWithTraversal("--scene " + std::string(GI_SHARED_SCENES) +
                                                  "/cornell-box-mcguire/CornellBox-Original.gltf --size 16x16"
                                                  " --method hpsf --out " +
                                                  dir + "/h.pfm",
                                              traversal, dir);
    if (run.refusedRayQueries) {
      EXPECT_EQ(run.rc, 1) << run.out;
      std::printf("this device has no ray queries: %s", run.out.c_str());
      continue;
    }
    ASSERT_EQ(run.rc, 0) << run.out;
    const nlohmann::json& j = run.stats;
    EXPECT_EQ(j["spp"], 1);
    EXPECT_EQ(j["traversal"], traversal);
  }
  std::string out;
  EXPECT_EQ(runTool("--scene x.gltf --traversal warp", out), 2) << out;
  EXPECT_NE(out.find("--traversal must be one of"), std::string::npos) << out;
}
