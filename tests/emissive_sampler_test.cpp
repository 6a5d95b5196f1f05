// Emissive triangles picked down their tree (LIGHT_SAMPLER_TREE, lights.glsl's giPrepareEmissive) with
// MIS against BSDF sampling (giEmissiveNeePdf walks the same choices up from the hit triangle's leaf):
// the same expectation as picking them by power, and less noise where many face away.
#include <cmath>
#include <cstdio>

#include "light_field.h"
#include "metrics.h"

class EmissiveSamplerTest : public LightFieldTest {};

namespace {

constexpr uint32_t kSize = 32;

// A glossy floor (GGX, roughness 0.3: BSDF sampling finds the emitters as often as NEE does) and a wall
// under 48 small emissive squares 1.2 to 1.8 m up, of radiances spanning 1:10, a third facing down, a
// third facing the wall and a third facing up (they light nothing here).
std::string emissiveField() {
  testscene::Description d;
  d.quads.push_back({{{-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}}, glm::vec3(0.6f), glm::vec3(0.0f), 0.3f});
  d.quads.push_back({{{-4, 0, -2}, {4, 0, -2}, {4, 3, -2}, {-4, 3, -2}}, glm::vec3(0.5f, 0.6f, 0.7f)});
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
  return testscene::write(d, "emissive_sampler_field");
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
