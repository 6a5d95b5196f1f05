// The reference path tracer against scenes with exact answers
// (../shared/scenes/README.md).
#include <cmath>

#include "gpu_test.h"

class ReferenceKnownAnswers : public GpuTest {};

// Closed furnace, albedo 0.5, emission 1 everywhere: L = Σ_{k=0..B+1} 0.5^k at every pixel.
TEST_F(ReferenceKnownAnswers, FurnaceMatchesGeometricSeriesForEachBounceLimit) {
  LoadedScene s;
  load(sharedScene("furnace/furnace_box.gltf"), s);
  for (uint32_t bounces : {0u, 1u, 2u, 3u, 16u}) {
    double expected = 0.0;
    for (uint32_t k = 0; k <= bounces + 1; ++k) expected += std::pow(0.5, double(k));
    engine::ReferenceSettings settings;
    settings.maxBounces = bounces;
    engine::ReferenceImages img = render(s, 32, 32, settings, 64);
    for (uint32_t c = 0; c < 3; ++c) {
      double mean = meanOf(img.final, c);
      EXPECT_NEAR(mean, expected, 0.01 * expected) << "B = " << bounces << ", channel " << c;
    }
    // Every pixel, not just the mean, must be near the answer (no bias hiding in corners).
    for (float v : img.final.pixels) ASSERT_NEAR(v, expected, 0.25 * expected) << "B = " << bounces;
  }
}

// Point light (1 W/sr) 1 m above an albedo-0.5 plane: centre radiance = 0.5/π.
TEST_F(ReferenceKnownAnswers, PointLightOverPlaneCentrePixel) {
  LoadedScene s;
  load(sharedScene("pointlight-plane/pointlight_plane.gltf"), s);
  engine::ReferenceSettings settings;
  settings.pixelJitter = false;  // the centre pixel's ray goes straight down
  for (uint32_t bounces : {0u, 3u}) {
    settings.maxBounces = bounces;
    engine::ReferenceImages img = render(s, 33, 33, settings, 4);
    for (uint32_t c = 0; c < 3; ++c) EXPECT_NEAR(img.final.at(16, 16, c), 0.159155, 0.01 * 0.159155);
  }
}

// Direct + indirect add up to the final image, and B = 0 has no indirect light.
TEST_F(ReferenceKnownAnswers, AovsAreConsistent) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  engine::ReferenceSettings settings;
  settings.maxBounces = 0;
  engine::ReferenceImages b0 = render(s, 24, 24, settings, 4);
  for (size_t i = 0; i < b0.final.pixels.size(); ++i) {
    EXPECT_FLOAT_EQ(b0.final.pixels[i], b0.direct.pixels[i]);
    EXPECT_EQ(b0.indirect.pixels[i], 0.0f);
  }
  settings.maxBounces = 3;
  settings.pixelJitter = false;  // every sample sees the same first hit, so albedo factors out exactly
  engine::ReferenceImages b3 = render(s, 24, 24, settings, 4);
  double indirectSum = 0.0;
  for (uint32_t y = 0; y < 24; ++y)
    for (uint32_t x = 0; x < 24; ++x)
      for (uint32_t c = 0; c < 3; ++c) {
        // Lambertian scene: final = direct + albedo × demodulated indirect, sample by sample.
        float recombined = b3.direct.at(x, y, c) + b3.albedo.at(x, y, c) * b3.indirect.at(x, y, c);
        EXPECT_NEAR(b3.final.at(x, y, c), recombined, 0.02f * std::max(1.0f, b3.final.at(x, y, c)));
        indirectSum += b3.indirect.at(x, y, c);
      }
  EXPECT_GT(indirectSum, 0.0);
}
