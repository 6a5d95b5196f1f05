// Emissive triangles picked down their tree (LIGHT_SAMPLER_TREE, lights.glsl's giPrepareEmissive) with
// MIS against BSDF sampling (giEmissiveNeePdf walks the same choices up from the hit triangle's leaf):
// the same expectation as picking them by power, and less noise where many face away.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "light_field.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "shared/gi_frame.h"

class EmissiveSamplerTest : public LightFieldTest {
 protected:
  // The scene at `path` under `sky`, its NEE with `sampler`.
  void loadUnderSky(const std::string& path, uint32_t sampler, const engine::Sky& sky, LoadedScene& out) {
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, out.scene, error)) << error;
    out.scene.lightSampler = sampler;
    out.scene.sky = sky;
    out.upload(ctx);
  }
};

namespace {

constexpr uint32_t kSize = 32;

// A glossy floor (GGX, roughness 0.3: BSDF sampling finds the emitters as often as NEE does) and a wall
// under 48 small emissive squares 1.2 to 1.8 m up, of radiances spanning 1:10, a third facing down, a
// third facing the wall and a third facing up (they light nothing here).
// `closed`: a room, the floor from the wall to 4 m behind the camera under a roof 3 m up between side walls
// and a back wall, so no sky reaches any surface.
std::string emissiveField(bool closed = false) {
  testscene::Description d;
  d.quads.push_back({{{-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}}, glm::vec3(0.6f), glm::vec3(0.0f), 0.3f});
  d.quads.push_back({{{-4, 0, -2}, {4, 0, -2}, {4, 3, -2}, {-4, 3, -2}}, glm::vec3(0.5f, 0.6f, 0.7f)});
  if (closed) {
    const glm::vec3 grey(0.5f);
    d.quads.push_back({{{-4, 3, -2}, {4, 3, -2}, {4, 3, 4}, {-4, 3, 4}}, grey});    // the roof, facing down
    d.quads.push_back({{{-4, 0, 4}, {-4, 0, -2}, {-4, 3, -2}, {-4, 3, 4}}, grey});  // the left wall, facing in
    d.quads.push_back({{{4, 0, -2}, {4, 0, 4}, {4, 3, 4}, {4, 3, -2}}, grey});      // the right wall
    d.quads.push_back({{{4, 0, 4}, {-4, 0, 4}, {-4, 3, 4}, {4, 3, 4}}, grey});      // behind the camera
  }
  for (uint32_t i = 0; i < 48; ++i) {
    const glm::vec3 c(-2.0f + 4.0f * float(i % 8) / 7.0f, 1.2f + 0.3f * float(i % 3),
                      -1.5f + 3.0f * float(i / 8) / 5.0f);
    const float h = 0.1f;
    const glm::vec3 emission = glm::vec3(1.0f + 9.0f * float((i * 7) % 48) / 48.0f) * 2.0f;
    testscene::Quad q;
    switch ((i / 2) % 3) {
      case 0:
        q.corner[0] = c + glm::vec3(-h, 0, -h), q.corner[1] = c + glm::vec3(h, 0, -h),  // facing down
            q.corner[2] = c + glm::vec3(h, 0, h), q.corner[3] = c + glm::vec3(-h, 0, h);
        break;
      case 1:
        q.corner[0] = c + glm::vec3(h, -h, 0), q.corner[1] = c + glm::vec3(-h, -h, 0),  // facing the wall
            q.corner[2] = c + glm::vec3(-h, h, 0), q.corner[3] = c + glm::vec3(h, h, 0);
        break;
      default:
        q.corner[0] = c + glm::vec3(-h, 0, h), q.corner[1] = c + glm::vec3(h, 0, h),  // facing up
            q.corner[2] = c + glm::vec3(h, 0, -h), q.corner[3] = c + glm::vec3(-h, 0, -h);
        break;
    }
    q.albedo = glm::vec3(0.2f);
    q.emission = emission;
    d.quads.push_back(q);
  }
  // Looking down from under the squares: the camera sees what they light, never them (a pixel that
  // caught one would be noise of its own, the same for every sampler).
  d.eye = {0, 1.0f, 3.0f};
  d.target = {0, 0, -0.5f};
  return testscene::write(d, closed ? "emissive_sampler_room" : "emissive_sampler_field");
}

// A dim map with a bright patch 39° up (a sun), so that NEE samples it: in column `sun` of 32 (12: behind
// the wall, which shadows the floor the camera sees; 28: behind the camera, lighting it).
engine::Sky sunnySky(uint32_t sun = 12) {
  engine::Sky sky;
  const uint32_t w = 32, h = 16;
  sky.map = engine::FloatImage(w, h, 3);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t c = 0; c < 3; ++c) sky.map.at(x, y, c) = y < h / 2 ? 0.3f + 0.1f * float(c) : 0.05f;
  for (uint32_t c = 0; c < 3; ++c) sky.map.at(sun, 4, c) = 60.0f;
  sky.radiance = glm::vec3(1.0f);
  sky.mapPath = "procedural";
  return sky;
}

// Raw's direct light, `frames` accumulated, averaged over seeds 1 to `seeds`.
engine::FloatImage meanOverSeeds(const engine::Context& ctx, LoadedScene& s, gi::Settings settings, uint32_t frames,
                                 uint32_t seeds) {
  engine::FloatImage sum;
  for (uint32_t seed = 1; seed <= seeds; ++seed) {
    settings.seed = seed;
    const engine::FloatImage run = rawDirectAfter(ctx, s, settings, kSize, frames, true);
    if (sum.pixels.empty())
      sum = run;
    else
      for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += run.pixels[i];
  }
  for (float& v : sum.pixels) v /= float(seeds);
  return sum;
}

}  // namespace

// Direct light only: the tree's image at 4096 spp against power's in 8×8 blocks (each within 3%, the
// whole image within 1%), and at 64 spp the tree's MSE (against
// power's 4096 spp) under power's: power spends a third of its picks on squares facing up.
TEST_F(EmissiveSamplerTest, TheTreesPicksKeepPowersExpectationWithLessNoise) {
  const std::string path = emissiveField();
  LoadedScene power, tree;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_POWER, power));
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, tree));
  ASSERT_EQ(gi::sceneInfo(power.gpu.scene).emissiveTriangles, 96u);
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  const gpu::GpuCamera cam = engine::makeGpuCamera(power.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun truth = referenceOrFail(ctx, power.gpu, cam, settings, 4096, 64);
  const engine::ReferenceRun many = referenceOrFail(ctx, tree.gpu, cam, settings, 4096, 64);
  uint32_t unlit = 0;
  const double worst = worstBlockDifference(many.images.final, truth.images.final, kSize, &unlit);
  const double meanPower = meanOf(truth.images.final), meanTree = meanOf(many.images.final);
  const double mse[2] = {
      metrics::mse(referenceOrFail(ctx, power.gpu, cam, settings, 64, 16).images.final, truth.images.final),
      metrics::mse(referenceOrFail(ctx, tree.gpu, cam, settings, 64, 16).images.final, truth.images.final)};
  // Power's picks of squares facing away trace no shadow ray: the tree's trace more, and bring light.
  std::printf(
      "tree: image mean %.5f against power's %.5f (%+.2f%%), worst 8x8 block %.2f%%; MSE at 64 spp: power "
      "%.3e, tree %.3e; rays: power %llu, tree %llu\n",
      meanTree, meanPower, 100.0 * (meanTree - meanPower) / meanPower, 100.0 * worst, mse[0], mse[1],
      (unsigned long long)truth.rays, (unsigned long long)many.rays);
  EXPECT_EQ(unlit, 0u) << "every block is lit";
  EXPECT_NEAR(meanTree, meanPower, 0.01 * meanPower);
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(mse[1], 0.8 * mse[0]) << "the tree skips the squares that cannot light a vertex (measured 0.73x)";
}

// Reservoirs over the emissive triangles (gi_reservoirs.comp: a triangle's sample point resampled by its
// unshadowed light, reused over the frames and the neighbours; the primary hit's NEE then samples only the
// sky, and its BSDF-sampled hits of the triangles count nothing), their candidates walked down the tree by
// each pixel, or drawn for each 8x8 group and shared (ReservoirSettings::groupCandidates: the tree at the
// group's surface mixed with power, its density the mixture's), two a pixel with the default share of power
// and one a pixel by power alone. Raw's direct light, 64 frames accumulated and averaged over 8 seeds, with the reservoirs and
// without (NEE down the triangles' tree with MIS): the same image in mean (within 1.5%) and in every 8x8
// block (within 5%); a frame after 15 with reservoirs under 0.7x the error of one without; no pixel of a
// frame brighter than 4x the brightest of the image without. A group draw weighed by the tree's chance
// alone (the mixture's density wrong by its power share) is off in mean by several times the bound.
TEST_F(EmissiveSamplerTest, ReservoirsResampleTheTrianglesWithTheirExpectation) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(loadWith(emissiveField(), gpu::LIGHT_SAMPLER_TREE, s));
  gi::Settings off, on;
  off.maxBounces = on.maxBounces = 1;
  off.reservoirs.enabled = false;
  ASSERT_TRUE(on.reservoirs.enabled);
  ASSERT_GT(gi::sceneInfo(s.gpu.scene).emissiveTriangles, on.reservoirs.emissiveMin);
  gi::Settings perPixel = on, group = on, groupByPower = on;
  perPixel.reservoirs.groupCandidates = 0;
  group.reservoirs.groupCandidates = 2;
  groupByPower.reservoirs.groupCandidates = 1;
  groupByPower.reservoirs.groupPowerShare = 1.0f;
  ASSERT_LT(group.reservoirs.groupPowerShare, 1.0f);
  const engine::FloatImage truth = meanOverSeeds(ctx, s, off, 64, 8);
  const float brightest = *std::max_element(truth.pixels.begin(), truth.pixels.end());
  const engine::FloatImage frameOff = rawDirectAfter(ctx, s, off, kSize, 16, false);
  const double errorOff = metrics::mse(frameOff, truth);
  const struct {
    const char* name;
    const gi::Settings& settings;
  } runs[] = {{"per pixel", perPixel}, {"the group's", group}, {"the group's by power", groupByPower}};
  for (const auto& run : runs) {
    const engine::FloatImage mean = meanOverSeeds(ctx, s, run.settings, 64, 8);
    const double relative = meanOf(mean) / meanOf(truth) - 1.0;
    const double worst = worstBlockDifference(mean, truth, kSize);
    const engine::FloatImage frameOn = rawDirectAfter(ctx, s, run.settings, kSize, 16, false);
    const double error = metrics::mse(frameOn, truth);
    const float peak = *std::max_element(frameOn.pixels.begin(), frameOn.pixels.end());
    std::printf(
        "emissive reservoirs, %s candidates: mean %+.2f%% of NEE's, worst 8x8 block %.2f%%; a frame's MSE %.3e "
        "against NEE's %.3e (%.2fx); its brightest pixel %.2f of the image's\n",
        run.name, 100.0 * relative, 100.0 * worst, error, errorOff, error / errorOff, peak / brightest);
    EXPECT_LT(std::abs(relative), 0.015) << run.name;
    EXPECT_LT(worst, 0.05) << run.name;
    EXPECT_LT(error, 0.7 * errorOff) << run.name;
    EXPECT_LT(peak, 4.0f * brightest) << run.name;
  }
}

// The sky as one node beside the emissive triangles' tree (giSkySelection): the area lights' shadow ray
// goes to the sky with its irradiance's share against the tree root's importance at the vertex, to the
// triangles with the rest, and BSDF-sampled hits of either weigh themselves by the same share. Under a
// map (a dim sky and a bright patch, so that NEE samples it), the tree's image at 4096 spp has power's
// expectation (which shares the ray half and half): each 8×8 block within 3%, the image within 1%; and
// at 64 spp less noise.
TEST_F(EmissiveSamplerTest, TheSkyAsANodeBesideTheTreeKeepsTheExpectation) {
  const engine::Sky sky = sunnySky();
  const std::string path = emissiveField();
  LoadedScene power, tree;
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(path, gpu::LIGHT_SAMPLER_POWER, sky, power));
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(path, gpu::LIGHT_SAMPLER_TREE, sky, tree));
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  const gpu::GpuCamera cam = engine::makeGpuCamera(power.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun truth = referenceOrFail(ctx, power.gpu, cam, settings, 4096, 64);
  const engine::ReferenceRun many = referenceOrFail(ctx, tree.gpu, cam, settings, 4096, 64);
  const double worst = worstBlockDifference(many.images.final, truth.images.final, kSize);
  const double meanPower = meanOf(truth.images.final), meanTree = meanOf(many.images.final);
  const double mse[2] = {
      metrics::mse(referenceOrFail(ctx, power.gpu, cam, settings, 64, 16).images.final, truth.images.final),
      metrics::mse(referenceOrFail(ctx, tree.gpu, cam, settings, 64, 16).images.final, truth.images.final)};
  std::printf(
      "under the sky: tree's mean %.5f against power's %.5f (%+.2f%%), worst 8x8 block %.2f%%; MSE at 64 "
      "spp: power %.3e, tree %.3e\n",
      meanTree, meanPower, 100.0 * (meanTree - meanPower) / meanPower, 100.0 * worst, mse[0], mse[1]);
  EXPECT_NEAR(meanTree, meanPower, 0.01 * meanPower);
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(mse[1], mse[0]) << "near the squares the tree takes them, far from them the sky (measured 0.82x)";
}

// The sky left to NEE at the budget the reservoirs take with a sky map among them (ReservoirSettings::
// rawNeighbours: `candidates` and `neighbours` then, not raw's own), so that the sky alone differs.
namespace {
gi::Settings skyLeftToNee() {
  gi::Settings s;
  s.reservoirs.rawCandidates = s.reservoirs.candidates;
  s.reservoirs.rawNeighbours = s.reservoirs.neighbours;
  return s;
}
}  // namespace

// The sky's map in the reservoirs beside the emissive triangles (ReservoirSettings::sky: a share of the
// candidates are directions from the map, resampled by the sky's light times the power heuristic of that
// density against the BSDF's; the primary hit's BSDF-sampled rays that leave the scene take the rest, and its
// area-light ray no longer goes to the sky). Under the sunny map, its sun lighting the floor the camera sees,
// raw's direct light (64 frames accumulated, 8 seeds) with the reservoirs holding the sky has NEE's
// expectation without reservoirs: the image within 1.5%, every 8x8 block within 5%; and frame 16, alone and
// accumulated, has less error than with the sky left to NEE (skyLeftToNee); under the power sampler (an equal share of the
// candidates for the sky) the same expectation.
TEST_F(EmissiveSamplerTest, ReservoirsResampleTheSkyMapWithItsExpectation) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(emissiveField(), gpu::LIGHT_SAMPLER_TREE, sunnySky(28), s));
  gi::Settings nee, withSky, withoutSky = skyLeftToNee();
  nee.maxBounces = withSky.maxBounces = withoutSky.maxBounces = 1;
  nee.reservoirs.enabled = false;
  ASSERT_TRUE(withSky.reservoirs.enabled);
  ASSERT_FALSE(withoutSky.reservoirs.sky) << "off by default: see ReservoirSettings::sky";
  withSky.reservoirs.sky = true;
  const engine::FloatImage truth = meanOverSeeds(ctx, s, nee, 64, 8);
  const engine::FloatImage mean = meanOverSeeds(ctx, s, withSky, 64, 8);
  const double relative = meanOf(mean) / meanOf(truth) - 1.0;
  const double worst = worstBlockDifference(mean, truth, kSize);
  // A frame alone, and 16 accumulated (the reservoirs' reuse correlates a pixel's frames).
  double error[2][2];
  for (bool accumulate : {false, true}) {
    error[accumulate][0] = metrics::mse(rawDirectAfter(ctx, s, withoutSky, kSize, 16, accumulate), truth);
    error[accumulate][1] = metrics::mse(rawDirectAfter(ctx, s, withSky, kSize, 16, accumulate), truth);
  }
  std::printf(
      "sky in the reservoirs: mean %+.2f%% of NEE's, worst 8x8 block %.2f%%; MSE against the sky left to NEE: "
      "frame 16 %.3e against %.3e (%.2fx), 16 frames accumulated %.3e against %.3e (%.2fx)\n",
      100.0 * relative, 100.0 * worst, error[0][1], error[0][0], error[0][1] / error[0][0], error[1][1], error[1][0],
      error[1][1] / error[1][0]);
  EXPECT_LT(std::abs(relative), 0.015);
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(error[0][1], 0.5 * error[0][0]) << "measured 0.33x";
  EXPECT_LT(error[1][1], 0.85 * error[1][0]) << "measured 0.65x (0.70x with the cap at 20)";
  // Under power, without the trees, the sky takes an equal share of the candidates beside the triangles:
  // the same expectation.
  LoadedScene power;
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(emissiveField(), gpu::LIGHT_SAMPLER_POWER, sunnySky(28), power));
  const engine::FloatImage powerMean = meanOverSeeds(ctx, power, withSky, 64, 8);
  const double powerRelative = meanOf(powerMean) / meanOf(truth) - 1.0;
  const double powerWorst = worstBlockDifference(powerMean, truth, kSize);
  std::printf("under power: mean %+.2f%%, worst 8x8 block %.2f%%\n", 100.0 * powerRelative, 100.0 * powerWorst);
  EXPECT_LT(std::abs(powerRelative), 0.015);
  EXPECT_LT(powerWorst, 0.05);
}

namespace {

// Raw's direct light against `truth` under `settings` and `reference` (the sky left to NEE): frame 16
// alone and 64 frames accumulated, each MSE averaged over seeds 1 to 4 (one seed's ratio spreads 0.8x to
// 1.3x either way): error[accumulated][0: reference, 1: settings].
struct SkyErrors {
  double error[2][2] = {};
  double ratio(bool accumulated) const { return error[accumulated][1] / error[accumulated][0]; }
};
SkyErrors skyErrorsOverSeeds(const engine::Context& ctx, LoadedScene& s, const gi::Settings& reference,
                             const gi::Settings& settings, const engine::FloatImage& truth) {
  SkyErrors e;
  for (uint32_t seed = 1; seed <= 4; ++seed)
    for (bool accumulate : {false, true})
      for (bool tried : {false, true}) {
        gi::Settings run = tried ? settings : reference;
        run.seed = seed;
        const engine::FloatImage image = rawDirectAfter(ctx, s, run, kSize, accumulate ? 64 : 16, accumulate);
        e.error[accumulate][tried] += metrics::mse(image, truth) / 4.0;
      }
  return e;
}

}  // namespace

// The sky in the reservoirs where the scene hides it (ReservoirSettings::sky). Its measured visibility
// (FrameStats::skyPicks: recent frames' sky picks that saw the sky, the factor the sky's share of the
// candidates and its target take): above 0.9 with the sun behind the camera lighting the floor, under 0.85
// with it behind the wall that shadows that floor, and at its least (1/256) in a closed room under the same
// map, where every pick fails. Against raw's direct light without reservoirs (8 seeds × 64 frames) both
// scenes keep NEE's expectation (image within 1.5%, 8x8 blocks within 5%), and against the sky left to NEE
// (the reservoirs holding the rest, at the sky's budget: skyLeftToNee; errors over 4 seeds): in the closed room at most 1.12x its error at
// frame 16 and over 64 accumulated frames (measured with the factor held at 1: 30x and 12x, seed 1; without
// the reservoirs' restart when it moves: 1.19x and 1.46x); with the sun behind the wall, the visibility
// reuse (a pixel's last-frame reservoir whose sky direction failed there is merged with weight 0) and the
// temporal merge's shorter cap while the sky is in the reservoirs (ReservoirSettings::skyMaxHistory, 4)
// take frame 16 under 0.85x (measured 0.79x; with the cap at 1 or 2, 0.98x and 0.86x; without the reuse,
// at a cap of 20, 1.00x) and 64 accumulated frames under 1.2x (1.08x; with the cap at 8 or at
// max_history's 20, 1.24x and 1.58x: the temporal reuse correlates a pixel's frames).
TEST_F(EmissiveSamplerTest, ReservoirsWeighTheSkyByItsMeasuredVisibility) {
  LoadedScene shadowed, sunlit, room;
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(emissiveField(), gpu::LIGHT_SAMPLER_TREE, sunnySky(12), shadowed));
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(emissiveField(), gpu::LIGHT_SAMPLER_TREE, sunnySky(28), sunlit));
  ASSERT_NO_FATAL_FAILURE(loadUnderSky(emissiveField(true), gpu::LIGHT_SAMPLER_TREE, sunnySky(28), room));
  gi::Settings nee, withSky, withoutSky = skyLeftToNee();
  nee.maxBounces = withSky.maxBounces = withoutSky.maxBounces = 1;
  nee.reservoirs.enabled = false;
  withSky.reservoirs.sky = true;
  // The visibility frame 20 weighed the sky by, and the picks behind it.
  auto skyVisibility = [&](LoadedScene& s, const char* name) {
    gi::Settings settings = withSky;
    settings.method = gi::Method::Raw;
    gi::FrameStats::SkyPicks picks;
    uint64_t tested = 0, visible = 0;
    renderAnimatedFrames(ctx, s, engine::makeSceneAnimation(s.scene), settings, kSize, 20, false,
                         [&](tools::ModuleSession& session) {
                           picks = gi::stats(session.module).skyPicks;
                           tested += picks.tested;
                           visible += picks.visible;
                         });
    std::printf("%s: %llu sky picks tested over 20 frames, %llu saw the sky; frame 20's visibility %.3f\n", name,
                (unsigned long long)tested, (unsigned long long)visible, picks.visibility);
    EXPECT_GT(tested, 64u) << name << ": enough picks for a ratio";
    return picks.visibility;
  };
  EXPECT_GT(skyVisibility(sunlit, "sun behind the camera"), 0.9f);
  EXPECT_LT(skyVisibility(shadowed, "sun behind the wall"), 0.85f);
  EXPECT_EQ(skyVisibility(room, "closed room"), GI_SKY_VISIBILITY_MIN);

  for (LoadedScene* s : {&room, &shadowed}) {
    const char* name = s == &room ? "closed room" : "sun behind the wall";
    const engine::FloatImage truth = meanOverSeeds(ctx, *s, nee, 64, 8);
    const engine::FloatImage mean = meanOverSeeds(ctx, *s, withSky, 64, 8);
    const double relative = meanOf(mean) / meanOf(truth) - 1.0;
    const double worst = worstBlockDifference(mean, truth, kSize);
    const SkyErrors e = skyErrorsOverSeeds(ctx, *s, withoutSky, withSky, truth);
    std::printf(
        "%s: mean %+.2f%% of NEE's, worst 8x8 block %.2f%%; MSE against the sky left to NEE (4 seeds): frame 16 "
        "%.3e against %.3e (%.2fx), 64 frames accumulated %.3e against %.3e (%.2fx)\n",
        name, 100.0 * relative, 100.0 * worst, e.error[0][1], e.error[0][0], e.ratio(false), e.error[1][1],
        e.error[1][0], e.ratio(true));
    EXPECT_LT(std::abs(relative), 0.015) << name;
    EXPECT_LT(worst, 0.05) << name;
    EXPECT_LE(e.ratio(false), s == &room ? 1.12 : 0.85) << name;
    EXPECT_LE(e.ratio(true), s == &room ? 1.12 : 1.2) << name;
  }
}

// The emissive triangles' tree follows gi::updateInstances: the squares moved (turned and shifted) through
// it render, under the tree, as the same scene loaded with them there, bit for bit (the tree is rebuilt
// from the same world positions), and not as the scene before the move.
TEST_F(EmissiveSamplerTest, SquaresMovedThroughUpdateInstancesLightAsTheSceneLoadedThere) {
  constexpr uint32_t kMoveSize = 24;
  const std::string path = emissiveField();
  LoadedScene moved, posed, still;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(path, moved.scene, error)) << error;
  moved.scene.lightSampler = gpu::LIGHT_SAMPLER_TREE;
  // The floor and the wall first, then the squares (emissiveField's order).
  ASSERT_EQ(moved.scene.instances.size(), 50u);
  for (size_t i = 2; i < moved.scene.instances.size(); ++i) moved.scene.instances[i].movable = true;
  still.scene = posed.scene = moved.scene;
  const glm::mat4 pose = glm::translate(glm::mat4(1.0f), glm::vec3(0.4f, -0.2f, 0.3f)) *
                         glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0));
  for (engine::Instance& instance : posed.scene.instances)
    if (instance.movable) instance.worldFromObject = pose * instance.worldFromObject;
  moved.upload(ctx);
  posed.upload(ctx);
  still.upload(ctx);
  moved.scene.instances = posed.scene.instances;
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordUpdateOrFail(ctx, cmd, moved.scene, moved.gpu); });
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  const engine::ReferenceImages a = render(moved, kMoveSize, kMoveSize, settings, 16);
  const engine::ReferenceImages b = render(posed, kMoveSize, kMoveSize, settings, 16);
  const engine::ReferenceImages c = render(still, kMoveSize, kMoveSize, settings, 16);
  size_t differ = 0;
  double moveDiff = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.final.pixels.size(); ++i) {
    differ += a.final.pixels[i] != b.final.pixels[i];
    moveDiff += std::fabs(double(c.final.pixels[i]) - b.final.pixels[i]);
    sum += std::fabs(double(b.final.pixels[i]));
  }
  std::printf("moved squares: %zu values differ from the scene loaded there; the move changed the image by %.1f%%\n",
              differ, 100.0 * moveDiff / sum);
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(moveDiff / sum, 0.05) << "the move should change the picture";
}

// Squares posed through device streams (gi::updateMeshVertices, as an engine's skinning hands vertices
// over) keep the emission table and tree of the pose they were loaded in, which the CPU built: the picks
// stay unbiased (each pick's chance over its triangle's area in the pose traced), so under power and under
// the tree the image has the expectation of the scene loaded in the new pose (direct light, 4096 spp: each
// 8×8 block within 3%, the image within 1%), and is not the image before the move (whose worst block is
// ten times as far off). The pose moves, turns
// and stretches them (their areas change by 1.3 × 0.8).
TEST_F(EmissiveSamplerTest, SquaresPosedThroughDeviceStreamsKeepTheExpectation) {
  const std::string path = emissiveField();
  const glm::mat4 pose = glm::translate(glm::mat4(1.0f), glm::vec3(0.4f, -0.2f, 0.3f)) *
                         glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0)) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(1.3f, 1.0f, 0.8f));
  for (uint32_t sampler : {gpu::LIGHT_SAMPLER_POWER, gpu::LIGHT_SAMPLER_TREE}) {
    SCOPED_TRACE(sampler);
    LoadedScene streamed, posed, still;
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, streamed.scene, error)) << error;
    streamed.scene.lightSampler = sampler;
    // The floor and the wall first, then the squares (emissiveField's order), each square a mesh of its own.
    ASSERT_EQ(streamed.scene.instances.size(), 50u);
    std::vector<uint32_t> squares;
    for (size_t i = 2; i < streamed.scene.instances.size(); ++i) squares.push_back(streamed.scene.instances[i].mesh);
    for (uint32_t m : squares) streamed.scene.meshes[m].deformable = true;
    still.scene = posed.scene = streamed.scene;
    for (size_t i = 2; i < posed.scene.instances.size(); ++i) {
      const engine::Instance& instance = posed.scene.instances[i];
      const glm::mat4 objectPose = glm::inverse(instance.worldFromObject) * pose * instance.worldFromObject;
      const glm::mat3 normalPose = glm::transpose(glm::inverse(glm::mat3(objectPose)));
      const engine::Mesh& mesh = posed.scene.meshes[instance.mesh];
      for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
        const engine::Primitive& primitive = posed.scene.primitives[p];
        for (uint32_t v = primitive.vertexOffset; v < primitive.vertexOffset + primitive.vertexCount; ++v) {
          posed.scene.positions[v] = glm::vec3(objectPose * glm::vec4(posed.scene.positions[v], 1.0f));
          posed.scene.normals[v] = glm::normalize(normalPose * posed.scene.normals[v]);
        }
      }
    }
    streamed.upload(ctx);
    posed.upload(ctx);
    still.upload(ctx);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    engine::Buffer positions =
        engine::createBufferFrom(ctx, std::span<const glm::vec3>(posed.scene.positions), usage, error);
    engine::Buffer normals =
        engine::createBufferFrom(ctx, std::span<const glm::vec3>(posed.scene.normals), usage, error);
    ASSERT_TRUE(error.empty()) << error;
    gi::MeshVertices streams;
    streams.devicePositions = {positions.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
    streams.deviceNormals = {normals.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      for (uint32_t m : squares) ASSERT_FALSE(gi::updateMeshVertices(streamed.gpu.scene, cmd, m, streams));
    });
    engine::ReferenceSettings settings;
    settings.maxBounces = 0;
    const gpu::GpuCamera cam = engine::makeGpuCamera(posed.scene.cameras[0], kSize, kSize, nullptr);
    const engine::ReferenceRun truth = referenceOrFail(ctx, posed.gpu, cam, settings, 4096, 64);
    const engine::ReferenceRun stale = referenceOrFail(ctx, streamed.gpu, cam, settings, 4096, 64);
    const engine::ReferenceRun before = referenceOrFail(ctx, still.gpu, cam, settings, 4096, 64);
    uint32_t unlit = 0;
    const double worst = worstBlockDifference(stale.images.final, truth.images.final, kSize, &unlit);
    const double meanTruth = meanOf(truth.images.final), meanStale = meanOf(stale.images.final);
    const double moved = worstBlockDifference(before.images.final, truth.images.final, kSize);
    std::printf(
        "%s, posed by device streams: mean %.5f against the scene loaded posed %.5f (%+.2f%%), worst 8x8 "
        "block %.2f%%; the pose moved the worst block by %.1f%%\n",
        sampler == gpu::LIGHT_SAMPLER_TREE ? "tree" : "power", meanStale, meanTruth,
        100.0 * (meanStale - meanTruth) / meanTruth, 100.0 * worst, 100.0 * moved);
    EXPECT_EQ(unlit, 0u) << "every block is lit";
    EXPECT_NEAR(meanStale, meanTruth, 0.01 * meanTruth);
    EXPECT_LT(worst, 0.03);
    EXPECT_GT(moved, 10.0 * worst) << "the pose should change the picture";
    engine::destroyBuffer(ctx, positions);
    engine::destroyBuffer(ctx, normals);
  }
}

// A scene lit by one quad lamp (the Cornell box's ceiling light, two triangles: LIGHT_EMISSIVE_TREE_MIN)
// keeps power's picks under the tree: the same image bit for bit, and the same rays.
TEST_F(EmissiveSamplerTest, OneQuadLampKeepsPowersPicksUnderTheTree) {
  const std::string path = sharedScene("cornell-box-mcguire/CornellBox-Original.gltf");
  LoadedScene power, tree;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_POWER, power));
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, tree));
  ASSERT_EQ(gi::sceneInfo(tree.gpu.scene).emissiveTriangles, gpu::LIGHT_EMISSIVE_TREE_MIN);
  engine::ReferenceSettings settings;
  const gpu::GpuCamera cam = engine::makeGpuCamera(power.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun a = referenceOrFail(ctx, power.gpu, cam, settings, 8, 8);
  const engine::ReferenceRun b = referenceOrFail(ctx, tree.gpu, cam, settings, 8, 8);
  EXPECT_TRUE(sameBits(a.images.final, b.images.final));
  EXPECT_EQ(a.rays, b.rays);
}
