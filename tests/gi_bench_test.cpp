// gi-bench end to end on a tiny image: every configuration gets a CSV row, and
// the plots and report appear; bad input is refused with a sentence.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run_process.h"

namespace {

int runBench(const std::string& args, std::string& output) { return runProcess(GI_BENCH_BINARY, args, output); }

}  // namespace

TEST(GiBenchTool, WritesResultsPlotsAndReport) {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / "gi_bench_test";
  std::filesystem::remove_all(dir);
  std::string out;
  int rc =
      runBench("--scene " + std::string(GI_SHARED_SCENES) +
                   "/cornell-box-mcguire/CornellBox-Original.gltf"
                   " --size 32x24 --methods raw --spp 1,2 --set raw.accumulate=0 --frames 3 --warmup 0 --max-bounces 2"
                   " --reference-spp 32 --camera-path --path-reference-spp 8 --validation --out " +
                   dir.string(),
               out);
  ASSERT_EQ(rc, 0) << out;
  std::ifstream csv(dir / "results.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("relmse"), std::string::npos);
  EXPECT_NE(header.find("equal_error_speedup"), std::string::npos);
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_NE(line.find("raw_trace:"), std::string::npos) << line;
  }
  EXPECT_EQ(rows, 2);
  // --camera-path: every timed frame of the walk has its own errors in series.csv.
  std::ifstream series(dir / "series.csv");
  int seriesRows = -1;  // the header
  while (std::getline(series, line)) ++seriesRows;
  EXPECT_EQ(seriesRows, 2 * 3);
  for (const char* f : {"tradeoff.png", "insets.png", "report.md", "run.txt", "images/reference.pfm"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  // The reference is cached: a second run renders none.
  rc = runBench(
      "--scene " + std::string(GI_SHARED_SCENES) +
          "/cornell-box-mcguire/CornellBox-Original.gltf"
          " --size 32x24 --methods raw --spp 1 --frames 1 --warmup 0 --max-bounces 2 --reference-spp 32 --no-plots"
          " --out " +
          dir.string(),
      out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_EQ(out.find("rendering reference"), std::string::npos) << out;
  // Under a sky the light differs: its own reference, not the cached one.
  rc = runBench(
      "--scene " + std::string(GI_SHARED_SCENES) +
          "/cornell-box-mcguire/CornellBox-Original.gltf"
          " --size 32x24 --methods raw --spp 1 --frames 1 --warmup 0 --max-bounces 2 --reference-spp 32 --no-plots"
          " --sky 0.5,0.5,0.5 --validation --out " +
          dir.string(),
      out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("rendering reference"), std::string::npos) << out;
  EXPECT_NE(out.find("_sky0.5-0.5-0.5"), std::string::npos) << out;
  // References from the G-buffer's hits are their own (…_gb), and raw's error against one of
  // many samples is about raw's noise: relMSE well above 0, finite.
  rc = runBench(
      "--scene " + std::string(GI_SHARED_SCENES) +
          "/cornell-box-mcguire/CornellBox-Original.gltf"
          " --size 32x24 --methods raw --spp 1 --frames 1 --warmup 0 --max-bounces 2 --reference-spp 64 --no-plots"
          " --reference-primary gbuffer --validation --out " +
          dir.string(),
      out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("rendering reference CornellBox-Original_cam0_32x24_b2_s64_gb (64 spp)"), std::string::npos)
      << out;
  EXPECT_TRUE(std::filesystem::exists(dir / "ref_CornellBox-Original_cam0_32x24_b2_s64_gb_final.exr"));
}

TEST(GiBenchTool, RefusesBadInput) {
  std::string out;
  EXPECT_EQ(runBench("--scene x.gltf --methods magic", out), 2) << out;
  EXPECT_NE(out.find("unknown method 'magic'"), std::string::npos) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods raw --spp 0", out), 2) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods raw --set raw.spp=0", out), 2) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods raw --set nonsense=1", out), 2) << out;
  EXPECT_EQ(runBench("--methods raw", out), 2) << out;
  EXPECT_EQ(runBench("--scene /no/such.gltf --methods raw", out), 1) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods hpsf --move-at 2 --invalidate-at-move sometimes", out), 2) << out;
  EXPECT_NE(out.find("neither all nor lights"), std::string::npos) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods hpsf --invalidate-at-move all", out), 2) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods raw --sky -1,0,0", out), 2) << out;
  EXPECT_NE(out.find("--sky -1,0,0"), std::string::npos) << out;
  EXPECT_EQ(runBench("--scene x.gltf --methods raw --reference-primary eyes", out), 2) << out;
  EXPECT_NE(out.find("'eyes' is not traced or gbuffer"), std::string::npos) << out;
}

// The moving-light experiment end to end: the jump, the engine's
// invalidation at it, recovery in the results and energy per frame in the series.
TEST(GiBenchTool, MovingLightExperiment) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gi_bench_move_test";
  std::filesystem::remove_all(dir);
  std::string out;
  int rc =
      runBench("--scene " + std::string(GI_SHARED_SCENES) +
                   "/cornell-box-mcguire/CornellBox-Original.gltf"
                   " --size 16x16 --methods hpsf --spp 1 --frames 8 --warmup 0 --move-at 2 --invalidate-at-move lights"
                   " --series --max-bounces 2 --reference-spp 16 --no-plots --validation --out " +
                   dir.string(),
               out);
  ASSERT_EQ(rc, 0) << out;
  std::ifstream series(dir / "series.csv");
  std::string header, line;
  std::getline(series, header);
  EXPECT_NE(header.find("energy_indirect"), std::string::npos) << header;
  EXPECT_NE(header.find("hash_stale_resets"), std::string::npos) << header;
  int rows = 0;
  while (std::getline(series, line)) ++rows;
  EXPECT_EQ(rows, 8);
  std::ifstream results(dir / "results.csv");
  std::getline(results, header);
  std::getline(results, line);
  auto split = [](const std::string& text) {
    std::vector<std::string> fields;
    std::stringstream in(text);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    return fields;
  };
  std::vector<std::string> names = split(header), values = split(line);
  auto column = std::find(names.begin(), names.end(), "move_recovery_frames");
  ASSERT_NE(column, names.end()) << header;
  ASSERT_LT(size_t(column - names.begin()), values.size()) << line;
  const int recovery = std::stoi(values[size_t(column - names.begin())]);
  EXPECT_GE(recovery, 1) << "a recovery frame among the 6 after the jump: " << line;
  EXPECT_LE(recovery, 6) << line;
}
