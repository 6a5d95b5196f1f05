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
  unload(s);
}
