// Axis-aligned filtering on glossy receivers: the specular term is estimated,
// filtered with its own band limit and multiplied by f0 afterwards, and runs
// only when the scene has glossy materials.
#include "gpu_test.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "procedural_scene.h"

class AafGlossyTest : public GpuTest {};

namespace {

// Mean of the final image over the pixels whose G-buffer albedo is the floor's.
double floorMean(const engine::ReferenceImages& module, const engine::FloatImage& image) {
  double sum = 0.0, n = 0.0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x)
      if (std::abs(module.albedo.at(x, y, 0) - 0.9f) < 0.02f) {
        for (int c = 0; c < 3; ++c) sum += image.at(x, y, c) / 3.0;
        n += 1.0;
      }
  return n > 0.0 ? sum / n : -1.0;
}

}  // namespace

// A metal floor (no diffuse lobe: every bit of its indirect light is
// specular) reflecting a lit white wall. Without the glossy term the floor's
// indirect light is lost; with it, the floor matches the reference.
TEST_F(AafGlossyTest, MetalFloorReflectsTheLitWall) {
  testscene::Description d;
  testscene::Quad floor{{{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}}, glm::vec3(0.9f)};
  floor.roughness = 0.4f;
  floor.metallic = 1.0f;
  d.quads.push_back(floor);
  d.quads.push_back({{{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, glm::vec3(0.8f)});  // back wall
  d.lights.push_back({{0, 1.0f, 0.2f}, glm::vec3(3.0f)});
  d.eye = {0, 0.6f, 1.8f};
  d.target = {0, 0.1f, -0.4f};
  LoadedScene s;
  load(testscene::write(d, "aaf_glossy_floor"), s);
  ASSERT_TRUE(s.gpu.desc.hasGlossyMaterials);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 1024);

  gi::Settings settings;
  settings.method = gi::Method::Aaf;
  settings.maxBounces = 2;
  settings.aaf.mu = 2.0f;
  auto render = [&](const engine::SceneGpu& scene, std::vector<std::string>* passes) {
    ScopedSession session(ctx);
    std::string error;
    EXPECT_TRUE(tools::createModuleSession(ctx, scene, {W, H}, settings, session, error)) << error;
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    engine::ReferenceImages out = tools::readModuleImages(ctx, session);
    if (passes)
      for (const gi::PassTiming& p : gi::stats(session.module).passes) passes->push_back(p.name);
    tools::destroyModuleSession(ctx, session);
    return out;
  };
  std::vector<std::string> glossyPasses, diffusePasses;
  engine::ReferenceImages glossy = render(s.gpu, &glossyPasses);
  engine::SceneGpu notGlossy = s.gpu;  // the same scene, described to the module as diffuse
  notGlossy.desc.hasGlossyMaterials = false;
  engine::ReferenceImages diffuseOnly = render(notGlossy, &diffusePasses);

  double reference = floorMean(glossy, ref.final);
  double withTerm = floorMean(glossy, glossy.final), withoutTerm = floorMean(glossy, diffuseOnly.final);
  double directOnly = floorMean(glossy, glossy.direct);
  ASSERT_GT(reference, 0.0) << "no floor pixels";
  std::printf("floor mean: reference %.4f, direct %.4f, aaf with glossy term %.4f, without %.4f\n", reference,
              directOnly, withTerm, withoutTerm);
  EXPECT_GT(reference - directOnly, 0.1 * reference) << "the wall's reflection should be a visible part of the floor";
  EXPECT_NEAR(withTerm, reference, 0.1 * reference);
  EXPECT_LT(withoutTerm, directOnly + 0.02 * reference) << "a metal floor has no diffuse indirect light";
  EXPECT_LT(metrics::mse(glossy.final, ref.final), 0.5 * metrics::mse(diffuseOnly.final, ref.final));
  for (float v : glossy.final.pixels) ASSERT_TRUE(std::isfinite(v));

  // The glossy filter passes run only for the glossy scene.
  auto has = [](const std::vector<std::string>& names, const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  EXPECT_TRUE(has(glossyPasses, "aaf_filter_glossy_rows"));
  EXPECT_TRUE(has(glossyPasses, "aaf_filter_glossy_edge_columns"));
  EXPECT_FALSE(has(diffusePasses, "aaf_filter_glossy_rows"));
  EXPECT_TRUE(has(diffusePasses, "aaf_filter_diffuse_rows"));
}

// A scene whose primitives all use diffuse, opaque materials is described as
// such, even though the loader always appends glTF's default material (a
// metal): the glossy and alpha-mask work never runs for it.
TEST_F(AafGlossyTest, UnusedMaterialsDoNotTurnOnGlossyOrAlphaWork) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  ASSERT_TRUE(gpu::materialHasGlossyLobe(s.scene.materials.back().metallic, s.scene.materials.back().roughness))
      << "the loader's fallback material is a metal";
  EXPECT_FALSE(s.gpu.desc.hasGlossyMaterials);
  EXPECT_FALSE(s.gpu.desc.hasAlphaMask);
}
