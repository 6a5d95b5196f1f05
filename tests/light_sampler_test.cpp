// gi::SceneCreateDesc::lightSampler (lights.glsl): LIGHT_SAMPLER_POWER picks
// one punctual light a vertex by its power and divides by its chance, so the
// image has the expectation of the exact sum over every light, and a vertex
// traces one shadow ray for them however many there are.
#include <cmath>
#include <cstdio>

#include "light_field.h"
#include "metrics.h"
#include "module_test_helpers.h"

class LightSamplerTest : public LightFieldTest {};

namespace {

constexpr uint32_t kSize = 32;

}  // namespace

// 32 lights, direct light only: each sampler's image at 2048 spp against the exact sum's at 64, in
// means over 8×8 blocks (each block's mean within 3%; the whole image's within 1%), and the rays a
// sample traces: one shadow ray with a picked light (the tree with a cut of one subtree), one a light
// with the exact sum. The tree's pick follows distance and angle, so at equal samples its pixels are
// closer to the exact sum than power's.
TEST_F(LightSamplerTest, PickedLightsHaveTheExactSumsExpectationAndOneShadowRayAVertex) {
  const std::string path = lightField(32, "light_sampler_field");
  LoadedScene exact;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_ALL, exact));
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  const gpu::GpuCamera cam = engine::makeGpuCamera(exact.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun all = referenceOrFail(ctx, exact.gpu, cam, settings, 64, 16);
  double equalSamplesMse[2] = {0.0, 0.0};
  for (uint32_t sampler : {gpu::LIGHT_SAMPLER_POWER, gpu::LIGHT_SAMPLER_TREE}) {
    const char* name = sampler == gpu::LIGHT_SAMPLER_POWER ? "power" : "tree";
    LoadedScene picked;
    ASSERT_NO_FATAL_FAILURE(loadWith(path, sampler, picked));
    const engine::ReferenceRun many = referenceOrFail(ctx, picked.gpu, cam, settings, 2048, 64);
    const engine::ReferenceRun few = referenceOrFail(ctx, picked.gpu, cam, settings, 64, 16);
    uint32_t unlit = 0;
    const double worst = worstBlockDifference(many.images.final, all.images.final, kSize, &unlit);
    ASSERT_EQ(unlit, 0u) << "every block is lit";
    const double mse = metrics::mse(few.images.final, all.images.final);
    equalSamplesMse[sampler == gpu::LIGHT_SAMPLER_TREE] = mse;
    const double meanAll = meanOf(all.images.final), meanPicked = meanOf(many.images.final);
    const double perSampleAll = double(all.rays) / (64.0 * kSize * kSize);
    const double perSamplePicked = double(many.rays) / (2048.0 * kSize * kSize);
    std::printf(
        "%s: image mean %.5f against every light's %.5f (%+.2f%%), worst 8x8 block %.2f%%; MSE at 64 spp "
        "%.3e; rays a sample %.2f against %.2f\n",
        name, meanPicked, meanAll, 100.0 * (meanPicked - meanAll) / meanAll, 100.0 * worst, mse, perSamplePicked,
        perSampleAll);
    EXPECT_NEAR(meanPicked, meanAll, 0.01 * meanAll) << name;
    EXPECT_LT(worst, 0.03) << name;
    // The primary ray, the BSDF's ray and one shadow ray a light (every light, all of which see every
    // pixel here), or one shadow ray for a picked light: 31 fewer.
    EXPECT_NEAR(perSampleAll - perSamplePicked, 31.0, 0.01) << name;
  }
  EXPECT_LT(equalSamplesMse[1], 0.5 * equalSamplesMse[0]) << "the tree's picks are better than power's";
}

// Spot lights aimed down, at the wall and up (lightField with spots): the tree's nodes bound the
// directions their lights aim at (shared/light_tree.h), so a vertex never picks a spot it is outside the
// cone of. Same expectation as the exact sum (as above), and at equal samples far less noise than
// power's picks, a third of which go to the spots aimed up.
TEST_F(LightSamplerTest, SpotsAimedAnywhereKeepTheExactSumsExpectationAndTheTreeSkipsTheOnesAimedAway) {
  const std::string path = lightField(48, "light_sampler_spots", false, true);
  LoadedScene exact, power, tree;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_ALL, exact));
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_POWER, power));
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, tree));
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  const gpu::GpuCamera cam = engine::makeGpuCamera(exact.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun all = referenceOrFail(ctx, exact.gpu, cam, settings, 64, 16);
  const engine::ReferenceRun many = referenceOrFail(ctx, tree.gpu, cam, settings, 2048, 64);
  const double treeMse =
      metrics::mse(referenceOrFail(ctx, tree.gpu, cam, settings, 64, 16).images.final, all.images.final);
  const double powerMse =
      metrics::mse(referenceOrFail(ctx, power.gpu, cam, settings, 64, 16).images.final, all.images.final);
  uint32_t unlit = 0;
  const double worst = worstBlockDifference(many.images.final, all.images.final, kSize, &unlit);
  const double meanAll = meanOf(all.images.final), meanTree = meanOf(many.images.final);
  std::printf(
      "spots, tree: image mean %.5f against every light's %.5f (%+.2f%%), worst 8x8 block %.2f%% (%u blocks "
      "unlit); MSE at 64 spp %.3e against power's %.3e\n",
      meanTree, meanAll, 100.0 * (meanTree - meanAll) / meanAll, 100.0 * worst, unlit, treeMse, powerMse);
  EXPECT_LT(unlit, 8u) << "most blocks are lit";
  EXPECT_NEAR(meanTree, meanAll, 0.01 * meanAll);
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(treeMse, 0.3 * powerMse) << "the tree skips the spots that cannot light a vertex";
}

// The tree with a cut of n subtrees: n shadow rays a vertex for the point lights, however many; with no
// more lights than that, every light on its own, the exact sum's image (up to the order of the sum);
// with more, the same expectation and, at equal samples, less noise the more subtrees.
TEST_F(LightSamplerTest, TheTreesCutIsExactUpToItsSizeAndItsRaysStayFixed) {
  engine::ReferenceSettings settings;
  settings.maxBounces = 1;
  const std::string few = lightField(4, "light_sampler_four");
  LoadedScene exact, tree;
  ASSERT_NO_FATAL_FAILURE(loadWith(few, gpu::LIGHT_SAMPLER_ALL, exact));
  ASSERT_NO_FATAL_FAILURE(loadWith(few, gpu::LIGHT_SAMPLER_TREE, tree, 4));
  const gpu::GpuCamera cam = engine::makeGpuCamera(exact.scene.cameras[0], kSize, kSize, nullptr);
  const engine::ReferenceRun a = referenceOrFail(ctx, exact.gpu, cam, settings, 16, 16);
  const engine::ReferenceRun b = referenceOrFail(ctx, tree.gpu, cam, settings, 16, 16);
  EXPECT_EQ(a.rays, b.rays);
  double worst = 0.0;
  for (size_t i = 0; i < a.images.final.pixels.size(); ++i)
    worst = std::max(worst, std::abs(double(a.images.final.pixels[i]) - double(b.images.final.pixels[i])) /
                                (std::abs(double(a.images.final.pixels[i])) + 1e-6));
  std::printf("4 lights, a cut of 4: worst relative difference to every light %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);
  exact.release();
  tree.release();

  settings.maxBounces = 0;
  const std::string many = lightField(32, "light_sampler_field");
  LoadedScene all;
  ASSERT_NO_FATAL_FAILURE(loadWith(many, gpu::LIGHT_SAMPLER_ALL, all));
  const engine::ReferenceRun truth = referenceOrFail(ctx, all.gpu, cam, settings, 64, 16);
  double previous = 1e30;
  for (uint32_t cut : {1u, 4u, 16u}) {
    LoadedScene s;
    ASSERT_NO_FATAL_FAILURE(loadWith(many, gpu::LIGHT_SAMPLER_TREE, s, cut));
    const engine::ReferenceRun r = referenceOrFail(ctx, s.gpu, cam, settings, 64, 16);
    double mse = 0.0;
    for (size_t i = 0; i < r.images.final.pixels.size(); ++i) {
      const double d = double(r.images.final.pixels[i]) - double(truth.images.final.pixels[i]);
      mse += d * d / double(r.images.final.pixels.size());
    }
    const double perSample = double(r.rays) / (64.0 * kSize * kSize);
    std::printf("32 lights, a cut of %u: MSE at 64 spp %.3e, rays a sample %.2f\n", cut, mse, perSample);
    EXPECT_NEAR(perSample, 2.0 + cut, 0.01) << "the primary ray, the BSDF's and one a subtree";
    EXPECT_LT(mse, previous) << "a cut of " << cut;
    previous = mse;
  }
}

// Bad values are named errors.
TEST_F(LightSamplerTest, BadSamplersAreNamedErrors) {
  LoadedScene s;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(lightField(4, "light_sampler_bad"), s.scene, error)) << error;
  auto expectRefused = [&](uint32_t sampler, uint32_t cut, const std::string& message) {
    s.scene.lightSampler = sampler;
    s.scene.lightTreeCut = cut;
    engine::SceneGpu gpu;
    std::string refused;
    EXPECT_FALSE(engine::createSceneGpu(ctx, s.scene, gpu, refused)) << "accepted: " << message;
    EXPECT_NE(refused.find(message), std::string::npos) << refused;
    EXPECT_EQ(refused.rfind(s.scene.sourcePath + ": ", 0), 0u) << "the file first: " << refused;
    engine::destroySceneGpu(ctx, gpu);
  };
  expectRefused(7, 4, "desc.lightSampler = 7");
  expectRefused(gpu::LIGHT_SAMPLER_TREE, 65, "desc.lightTreeCut = 65 is outside [1, 64]");
  expectRefused(gpu::LIGHT_SAMPLER_TREE, 0, "desc.lightTreeCut = 0 is outside [1, 64]");
}

// gi::LightSettings::sampler (catalogue lights.sampler) overrides the scene's sampler in the module's passes
// over the same tables: a scene made with the tree and told `all` renders what the scene made with `all`
// renders, bit for bit and ray for ray, and the reverse; the scene's own sampler (the reference's) stays.
TEST_F(LightSamplerTest, TheModulesSamplerSettingActsAsTheScenesWould) {
  const std::string path = lightField(32, "light_sampler_setting");
  LoadedScene all, tree;
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_ALL, all, 4));  // the same cut: the same tables
  ASSERT_NO_FATAL_FAILURE(loadWith(path, gpu::LIGHT_SAMPLER_TREE, tree, 4));
  ASSERT_FALSE(gi::picksPunctualLights(all.gpu.desc));
  ASSERT_TRUE(all.gpu.desc.picksPunctualLightsWith[gpu::LIGHT_SAMPLER_TREE]);
  const engine::SceneAnimation stillAll = engine::makeSceneAnimation(all.scene);
  const engine::SceneAnimation stillTree = engine::makeSceneAnimation(tree.scene);
  uint64_t rays[4] = {};
  auto render = [&](LoadedScene& s, const engine::SceneAnimation& still, gi::LightSampling sampler, uint64_t& count) {
    gi::Settings settings;
    settings.lights.sampler = sampler;
    uint32_t frame = 0;
    return renderAnimatedFrames(ctx, s, still, settings, kSize, 3, false, [&](tools::ModuleSession& session) {
      gi::FrameStats stats;
      if (gi::frameStats(session.module, frame++, stats)) count = stats.raysTraced;
    });
  };
  const engine::ReferenceImages allScene = render(all, stillAll, gi::LightSampling::Scene, rays[0]);
  const engine::ReferenceImages treeToldAll = render(tree, stillTree, gi::LightSampling::All, rays[1]);
  const engine::ReferenceImages treeScene = render(tree, stillTree, gi::LightSampling::Scene, rays[2]);
  const engine::ReferenceImages allToldTree = render(all, stillAll, gi::LightSampling::Tree, rays[3]);
  std::printf("rays a frame: all %llu, tree told all %llu, tree %llu, all told tree %llu\n",
              (unsigned long long)rays[0], (unsigned long long)rays[1], (unsigned long long)rays[2],
              (unsigned long long)rays[3]);
  EXPECT_TRUE(sameBits(allScene.final, treeToldAll.final));
  EXPECT_TRUE(sameBits(treeScene.final, allToldTree.final));
  EXPECT_FALSE(sameBits(allScene.final, treeScene.final));
  EXPECT_EQ(rays[0], rays[1]);
  EXPECT_EQ(rays[2], rays[3]);
  EXPECT_GT(rays[0], rays[2]) << "every light costs more rays than the tree's cut";
}
