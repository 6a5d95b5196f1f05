// --sky values and the sky map's sampling tables, on the CPU.
#include <gtest/gtest.h>
#include <numbers>

#include <cmath>
#include <filesystem>

#include "scene/sky_tables.h"
#include "sky.h"

namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("gi_sky_unit_" + name)).string();
}

}  // namespace

TEST(Sky, ConstantColoursParseAndBadOnesAreNamed) {
  engine::Sky sky;
  std::string error;
  ASSERT_TRUE(engine::parseSky("0.5,1,2.5", sky, error)) << error;
  EXPECT_EQ(sky.radiance, glm::vec3(0.5f, 1.0f, 2.5f));
  EXPECT_FALSE(sky.hasMap());
  EXPECT_TRUE(sky.enabled());
  ASSERT_TRUE(engine::parseSky("0,0,0", sky, error)) << error;
  EXPECT_FALSE(sky.enabled()) << "a black sky is no sky";
  for (const char* bad : {"1,2", "1,2,3,4", "1,,3", "a,b,c", "1,-2,3", "nan,1,1", "inf,1,1", "1,2,3x"}) {
    engine::Sky untouched;
    error.clear();
    EXPECT_FALSE(engine::parseSky(bad, untouched, error)) << bad;
    EXPECT_NE(error.find(bad), std::string::npos) << bad << ": " << error;
    EXPECT_FALSE(untouched.enabled()) << bad;
  }
}

TEST(Sky, MapsLoadAndBadFilesAreNamed) {
  engine::FloatImage map(4, 2, 3);
  for (float& v : map.pixels) v = 0.25f;
  std::string error;
  const std::string good = tempPath("good.pfm");
  ASSERT_TRUE(engine::writeImage(good, map, error)) << error;
  engine::Sky sky;
  ASSERT_TRUE(engine::parseSky(good, sky, error)) << error;
  EXPECT_TRUE(sky.hasMap());
  EXPECT_EQ(sky.map.width, 4u);
  EXPECT_EQ(sky.radiance, glm::vec3(1.0f)) << "a map's scale is 1";

  error.clear();
  EXPECT_FALSE(engine::parseSky(tempPath("missing.exr"), sky, error));
  EXPECT_NE(error.find("missing.exr"), std::string::npos) << error;

  map.at(3, 1, 2) = -1.0f;
  const std::string negative = tempPath("negative.pfm");
  ASSERT_TRUE(engine::writeImage(negative, map, error)) << error;
  error.clear();
  EXPECT_FALSE(engine::parseSky(negative, sky, error));
  EXPECT_NE(error.find("negative.pfm"), std::string::npos) << error;
  EXPECT_NE(error.find("(3, "), std::string::npos) << "names the texel: " << error;
  std::filesystem::remove(good);
  std::filesystem::remove(negative);
}

// Row probabilities follow Σ luminance × sin θ; columns the luminance within
// the row; every table rises to exactly 1.
TEST(Sky, DistributionFollowsLuminanceTimesSinTheta) {
  const uint32_t w = 8, h = 4;
  engine::FloatImage map(w, h, 3);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t c = 0; c < 3; ++c) map.at(x, y, c) = float(1 + x + 10 * y);
  float sum = 0.0f;
  std::vector<float> t = gi::skyDistribution(map.pixels.data(), map.width, map.height, map.channels, sum);
  ASSERT_EQ(t.size(), size_t(h + w * h));
  double expectedSum = 0.0;
  std::vector<double> rows(h, 0.0);
  for (uint32_t y = 0; y < h; ++y) {
    const double sinTheta = std::sin(std::numbers::pi * (y + 0.5) / h);
    for (uint32_t x = 0; x < w; ++x) rows[y] += (1 + x + 10 * y) * sinTheta;  // grey: luminance = the value
    expectedSum += rows[y];
  }
  EXPECT_NEAR(sum, expectedSum, 1e-4 * expectedSum);
  double previous = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    EXPECT_NEAR(t[y] - previous, rows[y] / expectedSum, 1e-5) << "row " << y;
    previous = t[y];
    const float* row = &t[h + y * w];
    for (uint32_t x = 0; x < w; ++x) {
      const double column = (1 + x + 10 * y) / (rows[y] / std::sin(std::numbers::pi * (y + 0.5) / h));
      EXPECT_NEAR(row[x] - (x ? row[x - 1] : 0.0f), column, 1e-5) << x << ", " << y;
    }
    EXPECT_EQ(row[w - 1], 1.0f);
  }
  EXPECT_EQ(t[h - 1], 1.0f);
}

TEST(Sky, BlackMapHasZeroSumAndUniformTables) {
  engine::FloatImage map(4, 2, 3);
  float sum = 1.0f;
  std::vector<float> t = gi::skyDistribution(map.pixels.data(), map.width, map.height, map.channels, sum);
  EXPECT_EQ(sum, 0.0f);
  EXPECT_FLOAT_EQ(t[0], 0.5f);
  EXPECT_FLOAT_EQ(t[1], 1.0f);
  EXPECT_FLOAT_EQ(t[2], 0.25f);
  EXPECT_FLOAT_EQ(t[5], 1.0f);
}
