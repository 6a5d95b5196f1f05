// Many-light scenes (issue 31): engine::spreadPointLights keeps the scene's
// light as a whole (total intensity per channel, height) and only spreads it;
// the hall we ship (assets/make_light_hall.py) loads with its 256 lamps.
#include <gtest/gtest.h>

#include "gltf_loader.h"
#include "light_grid.h"

namespace {

engine::Scene conference() {
  engine::Scene scene;
  std::string error;
  EXPECT_TRUE(engine::loadGltf(std::string(GI_SHARED_SCENES) + "/conference-ward/conference-ward.gltf", scene, error))
      << error;
  return scene;
}

}  // namespace

TEST(LightGrid, SpreadsThePointLightsTotalIntensityOverTheCount) {
  engine::Scene scene = conference();
  glm::vec3 before{0.0f};
  float height = 0.0f;
  uint32_t points = 0;
  for (const engine::PunctualLight& l : scene.lights)
    if (l.type == engine::LightType::Point) {
      before += l.intensity;
      height += l.position.y;
      ++points;
    }
  ASSERT_GT(points, 0u);
  height /= float(points);
  const engine::Bounds bounds = scene.worldBounds();
  for (uint32_t count : {1u, 7u, 1024u}) {
    engine::Scene spread = scene;
    std::string error;
    ASSERT_TRUE(engine::spreadPointLights(spread, count, error)) << error;
    ASSERT_EQ(spread.lights.size(), count + (scene.lights.size() - points));
    glm::vec3 after{0.0f};
    for (const engine::PunctualLight& l : spread.lights) {
      if (l.type != engine::LightType::Point) continue;
      after += l.intensity;
      EXPECT_NEAR(l.position.y, height, 1e-4f * (bounds.max.y - bounds.min.y));
      EXPECT_GT(l.position.x, bounds.min.x);
      EXPECT_LT(l.position.x, bounds.max.x);
      EXPECT_GT(l.position.z, bounds.min.z);
      EXPECT_LT(l.position.z, bounds.max.z);
    }
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(after[c], before[c], 1e-4f * before[c]) << count << " lights, channel " << c;
    // No two lights at one place.
    for (size_t i = 1; i < spread.lights.size(); ++i)
      EXPECT_NE(spread.lights[i].position, spread.lights[i - 1].position) << count << " lights";
  }
}

TEST(LightGrid, NoPointLightOrZeroCountIsANamedError) {
  engine::Scene scene = conference();
  std::string error;
  EXPECT_FALSE(engine::spreadPointLights(scene, 0, error));
  EXPECT_NE(error.find("0 asked for"), std::string::npos) << error;
  scene.lights.clear();
  error.clear();
  EXPECT_FALSE(engine::spreadPointLights(scene, 16, error));
  EXPECT_NE(error.find("no point light"), std::string::npos) << error;
  EXPECT_NE(error.find("conference-ward.gltf"), std::string::npos) << error;
}

TEST(LightGrid, TheShippedHallLoadsWithItsLamps) {
  engine::Scene scene;
  std::string error;
  ASSERT_TRUE(engine::loadGltf(std::string(GI_ASSETS) + "/light_hall/light_hall.gltf", scene, error)) << error;
  ASSERT_EQ(scene.lights.size(), 256u);
  glm::vec3 total{0.0f};
  for (const engine::PunctualLight& l : scene.lights) {
    EXPECT_EQ(l.type, engine::LightType::Point);
    EXPECT_NEAR(l.position.y, 4.6f, 1e-5f) << l.name;
    total += l.intensity;
  }
  EXPECT_NEAR(total.x, 256 * 0.75f, 1e-3f) << "0.75 cd per lamp, colour (1, 0.85, 0.7)";
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.cameras[0].name, "entrance");
  EXPECT_FALSE(scene.hasEmissiveGeometry()) << "lit by its lamps alone";
}
