// The demo as a user runs it without a display: headless frames and CSV,
// budget mode on a static scene, and a clear error for a bad scene file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "run_process.h"

namespace fs = std::filesystem;

namespace {

int runGame(const std::string& args, std::string& output) {
  return runProcess("env -u DISPLAY " GI_SAMPLE_GAME_BINARY, args, output);
}

// The CSV's rows as column → value.
std::vector<std::map<std::string, std::string>> csvRows(const fs::path& path) {
  std::ifstream f(path);
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(f, line);) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string field; std::getline(s, field, ',');) fields.push_back(field);
    if (header.empty()) {
      header = fields;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

std::vector<std::string> csvLines(const fs::path& path) {
  std::ifstream f(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(f, line);) lines.push_back(line);
  return lines;
}

}  // namespace

TEST(SampleGame, HeadlessWritesTheWalkthroughFramesAndTheCsv) {
  fs::path out = fs::temp_directory_path() / "gi_sample_game_headless";
  fs::remove_all(out);
  std::string output;
  int rc = runGame("--frames 3 --size 64x36 --window-size 320x180 --validation --out " + out.string(), output);
  ASSERT_EQ(rc, 0) << output;
  EXPECT_NE(output.find("no display: running headless"), std::string::npos) << output;
  for (int f = 0; f < 3; ++f) EXPECT_TRUE(fs::exists(out / ("frame_0000" + std::to_string(f) + ".png"))) << f;
  std::vector<std::string> lines = csvLines(out / "benchmark.csv");
  ASSERT_EQ(lines.size(), 4u) << "a header and one row per frame";
  // The default method, svgf: its passes are the columns.
  EXPECT_EQ(
      lines[0].rfind(
          "frame,seconds,cpu_ms,gbuffer_ms,module_ms,rays,spp,raw_trace_ms,temporal_ms,svgf_variance_ms,svgf_atrous_ms",
          0),
      0u)
      << lines[0];
}

// Budget mode on a static scene: the controller's convergence is asserted in
// the Budget tests (a cost model); here the real run prints what it achieved. The target is a quarter of
// what the same frames take unconstrained on this device (measured first: on lavapipe about 250 ms, on an
// H200 about 32 ms, so a fixed target was nothing to cut there). ctest runs two tests at
// once on two cores, so a neighbour can slow the last frames after the controller settled: the bound on
// the achieved time is the mean of the last 8 of 24 frames within 2x of the target, not a timing claim.
TEST(SampleGame, BudgetModeReportsTheAchievedTimeOnAStaticScene) {
  fs::path out = fs::temp_directory_path() / "gi_sample_game_budget";
  const std::string scene = "--still --method aaf --set aaf.mu=4 --size 64x36 --window-size 320x180 ";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(runGame("--frames 4 --benchmark 4 " + scene + "--out " + out.string(), output), 0) << output;
  const auto free = csvRows(out / "benchmark.csv");
  ASSERT_EQ(free.size(), 4u);
  // Frames 2 and 3: the programs compiled at frame 0 stay out of the measure.
  const double unconstrainedMs = 0.5 * (std::stod(free[2].at("module_ms")) + std::stod(free[3].at("module_ms")));
  const int targetMs = std::max(1, int(std::lround(unconstrainedMs / 4.0)));  // --budget-ms takes whole ms
  fs::remove_all(out);
  int rc = runGame(
      "--frames 24 " + scene + "--budget-ms " + std::to_string(targetMs) + " --benchmark 24 --out " + out.string(),
      output);
  ASSERT_EQ(rc, 0) << output;
  size_t at = output.find("budget mode: target " + std::to_string(targetMs) + ".0 ms, last frame ");
  ASSERT_NE(at, std::string::npos) << output;
  std::printf("unconstrained %.1f ms a frame; %s", unconstrainedMs, output.substr(output.rfind("frames ")).c_str());
  const auto rows = csvRows(out / "benchmark.csv");
  ASSERT_EQ(rows.size(), 24u);
  auto rays = [&](size_t f) { return std::stod(rows[f].at("rays")); };
  double lastMs = 0.0;
  for (size_t f = 16; f < 24; ++f) lastMs += std::stod(rows[f].at("module_ms")) / 8.0;
  std::printf("rays: frame 0 %.0f, frame 23 %.0f; module ms over frames 16-23 %.1f\n", rays(0), rays(23), lastMs);
  // Unconstrained, a frame takes four times the target: the budget cuts the rays to well under half, and
  // holds the module's time near the target.
  EXPECT_LT(rays(23), 0.5 * rays(0)) << "the budget cut the rays";
  EXPECT_GT(lastMs, 0.5 * targetMs);
  EXPECT_LT(lastMs, 2.0 * targetMs);
}

// Budget mode changes the ray budget every frame; the history it accumulates must survive it (issue 35):
// svgf with a still camera, 40 frames, with and without a 5 ms budget: the frames of history behind the
// median pixel at the last frame are the same, and at least 16.
TEST(SampleGame, BudgetModeKeepsTheHistory) {
  uint32_t history[2] = {0, 0};
  for (int budget = 0; budget < 2; ++budget) {
    fs::path out = fs::temp_directory_path() / ("gi_sample_game_history_" + std::to_string(budget));
    fs::remove_all(out);
    std::string output;
    int rc = runGame(std::string("--still --method svgf --size 64x36 --window-size 320x180 --benchmark 40 ") +
                         (budget ? "--budget-ms 5 " : "") + "--out " + out.string(),
                     output);
    ASSERT_EQ(rc, 0) << output;
    const auto rows = csvRows(out / "benchmark.csv");
    ASSERT_EQ(rows.size(), 40u);
    history[budget] = uint32_t(std::stoul(rows.back().at("history_frames")));
    if (budget) {
      EXPECT_NE(rows.front().at("rays"), rows.back().at("rays")) << "the budget changed the rays";
    }
  }
  std::printf("history frames at frame 40: %u without a budget, %u with 5 ms\n", history[0], history[1]);
  EXPECT_EQ(history[1], history[0]);
  EXPECT_GE(history[0], 16u);
}

// The demo's animated frames (the light and block move every frame, gi::updateInstances and
// gi::updateLights recorded into each frame's command buffer) under synchronization validation: from the
// third frame on each waits on one fence (its slot's), waits for no idle queue or device, creates and
// allocates nothing, and the module's device allocations stay as they are.
TEST(SampleGame, AnimatedFramesWaitOnOneFenceAndCreateNothing) {
  fs::path out = fs::temp_directory_path() / "gi_sample_game_in_flight";
  fs::remove_all(out);
  std::string output;
  int rc =
      runGame("--size 64x36 --window-size 320x180 --benchmark 100 --sync-validation --out " + out.string(), output);
  ASSERT_EQ(rc, 0) << output;  // 3: validation reported something
  const auto rows = csvRows(out / "benchmark.csv");
  ASSERT_EQ(rows.size(), 100u);
  for (size_t f = 2; f < rows.size(); ++f) {
    EXPECT_LE(std::stoi(rows[f].at("fence_waits")), 1) << "frame " << f;
    EXPECT_EQ(rows[f].at("idle_waits"), "0") << "frame " << f;
    EXPECT_EQ(rows[f].at("creations"), "0") << "frame " << f;
    EXPECT_EQ(rows[f].at("module_allocations"), rows[2].at("module_allocations")) << "frame " << f;
  }
}

// A bad scene file: exit status 1 (no crash), one line naming the file and what is wrong with it.
TEST(SampleGame, AMalformedSceneIsNamedInTheError) {
  const std::pair<const char*, const char*> cases[] = {
      {"not_json.gltf", "parse error at line 1"},
      {"index_out_of_range.gltf", "index 2 is 7, out of range for 3 vertices"},
      {"missing_buffer.gltf", "File not found : does_not_exist.bin"},
  };
  for (auto [file, problem] : cases) {
    std::string output;
    int rc = runGame(std::string("--frames 1 --scene " GI_TEST_DATA "/malformed/") + file, output);
    EXPECT_EQ(rc, 1) << file << ": " << output;
    EXPECT_NE(output.find(std::string("sample_game: ") + GI_TEST_DATA + "/malformed/" + file + ": "), std::string::npos)
        << output;
    EXPECT_NE(output.find(problem), std::string::npos) << file << ": " << output;
  }
}

TEST(SampleGame, HelpListsTheOptionsAndExitsZero) {
  std::string output;
  EXPECT_EQ(runGame("--help", output), 0) << output;
  EXPECT_NE(output.find("usage: sample_game"), std::string::npos) << output;
  EXPECT_NE(output.find("--traversal"), std::string::npos) << output;
  EXPECT_NE(output.find("--sky"), std::string::npos) << output;
}

// A method picked in the overlay is switched to only once its programs are
// ready, made on a thread of the demo's (and, on lavapipe, compiled on a
// second device into the shader cache) while the old method keeps rendering:
// with a cold cache, frames keep coming, and none takes anywhere near what
// readying took (a frame that compiled would).
TEST(SampleGame, AMethodSwitchKeepsTheFramesComingWhileItsProgramsAreReadied) {
  const fs::path out = fs::temp_directory_path() / "gi_sample_game_switch";
  const fs::path cache = fs::temp_directory_path() / "gi_sample_game_switch_cache";  // cold: everything compiles
  fs::remove_all(out);
  fs::remove_all(cache);
  std::string output;
  const int rc = runProcess(
      "env -u DISPLAY MESA_SHADER_CACHE_DIR=" + cache.string() + " " GI_SAMPLE_GAME_BINARY,
      "--benchmark 300 --size 64x36 --window-size 320x180 --switch-at 3:gif --validation --out " + out.string(),
      output);
  ASSERT_EQ(rc, 0) << output;
  const auto rows = csvRows(out / "benchmark.csv");
  ASSERT_EQ(rows.size(), 300u);
  uint32_t readyingFrames = 0, switchedAt = 0;
  double readyingMs = 0.0, longestMs = 0.0;
  // The last two rows are timed at exit, after the window's wait for the GPU: left out.
  for (uint32_t f = 3; f + 2 < rows.size(); ++f) {
    const double cpuMs = std::stod(rows[f].at("cpu_ms"));
    longestMs = std::max(longestMs, cpuMs);
    if (rows[f].at("readying") == "1") {
      ++readyingFrames;
      readyingMs += cpuMs;
      EXPECT_EQ(rows[f].at("method"), "svgf") << "frame " << f << ": the old method renders meanwhile";
    }
    if (!switchedAt && rows[f].at("method") == "gif") switchedAt = f;
  }
  std::printf("readying: %u frames, %.0f ms; switched at frame %u; longest frame after the request %.0f ms\n",
              readyingFrames, readyingMs, switchedAt, longestMs);
  EXPECT_GE(readyingFrames, 2u) << "frames kept coming while the programs were readied";
  ASSERT_GT(switchedAt, 0u) << "the switch happened";
  for (uint32_t f = switchedAt; f < rows.size(); ++f) EXPECT_EQ(rows[f].at("method"), "gif") << f;
  EXPECT_LT(longestMs, 0.5 * readyingMs) << "no frame stalled for a compile";
}
