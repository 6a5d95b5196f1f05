// The reference is deterministic for a seed, and the seed matters.
#include "gpu_test.h"

class Determinism : public GpuTest {};

TEST_F(Determinism, SameSeedSameImageDifferentSeedDifferentImage) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  engine::ReferenceSettings settings;
  settings.maxBounces = 4;
  settings.seed = 7;
  engine::ReferenceImages a = render(s, 32, 32, settings, 4);
  engine::ReferenceImages b = render(s, 32, 32, settings, 4);
  settings.seed = 8;
  engine::ReferenceImages c = render(s, 32, 32, settings, 4);
  EXPECT_EQ(a.final.pixels, b.final.pixels);
  EXPECT_EQ(a.indirect.pixels, b.indirect.pixels);
  EXPECT_NE(a.final.pixels, c.final.pixels);
}

// A textured scene (Sponza: 11 JPEG textures with mip chains, a directional
// light) loads, uploads and traces under validation, and the textures show.
class TexturedScene : public GpuTest {};

TEST_F(TexturedScene, SponzaRendersUnderValidation) {
  LoadedScene s;
  load(sharedScene("sponza-dabrovic/sponza-dabrovic.gltf"), s);
  EXPECT_EQ(s.gpu.textures.size(), s.scene.textures.size());
  EXPECT_GE(s.scene.textures.size(), 10u);
  EXPECT_GT(s.gpu.textures[0].mipLevels, 5u);
  engine::ReferenceSettings settings;
  settings.maxBounces = 1;
  engine::ReferenceImages img = render(s, 24, 16, settings, 1);
  double albedoVariation = 0.0;
  for (size_t i = 3; i < img.albedo.pixels.size(); ++i)
    albedoVariation += std::abs(img.albedo.pixels[i] - img.albedo.pixels[i - 3]);
  EXPECT_GT(albedoVariation, 1.0) << "textured albedo should vary across the image";
  for (float v : img.final.pixels) ASSERT_TRUE(std::isfinite(v));
}
