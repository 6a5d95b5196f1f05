// CPU-side building blocks: Morton ordering (the module's), image files, camera maths, scene animation.
#include <gtest/gtest.h>

#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "gi/device.h"
#include "animation.h"
#include "camera.h"
#include "image_io.h"
#include "scene/morton_order.h"
#include "shared/gi_filters.h"

TEST(Morton, CodesInterleaveAxesAndOrderPreservesLocality) {
  glm::vec3 lo(0.0f), hi(1.0f);
  EXPECT_EQ(gi::mortonCode(lo, lo, hi), 0u);
  EXPECT_EQ(gi::mortonCode(hi, lo, hi), (1u << 30) - 1u);  // all 30 bits set
  // x is the most significant axis of each triple.
  EXPECT_GT(gi::mortonCode({0.6f, 0.0f, 0.0f}, lo, hi), gi::mortonCode({0.0f, 0.6f, 0.0f}, lo, hi));
  std::vector<glm::vec3> points = {{0.9f, 0.9f, 0.9f}, {0.1f, 0.1f, 0.1f}, {0.88f, 0.9f, 0.9f}, {0.12f, 0.1f, 0.1f}};
  std::vector<uint32_t> order = gi::mortonOrder(points);
  ASSERT_EQ(order.size(), 4u);
  // Near points end up adjacent.
  EXPECT_EQ(std::abs(int(std::find(order.begin(), order.end(), 1u) - std::find(order.begin(), order.end(), 3u))), 1);
  EXPECT_EQ(std::abs(int(std::find(order.begin(), order.end(), 0u) - std::find(order.begin(), order.end(), 2u))), 1);
}

TEST(Morton, TriangleSortKeepsEveryTriangleWholeAndIsStable) {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  for (int i = 0; i < 30; ++i) {
    float x = float((i * 7) % 30);
    positions.insert(positions.end(), {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}});
    indices.insert(indices.end(), {uint32_t(3 * i), uint32_t(3 * i + 1), uint32_t(3 * i + 2)});
  }
  std::vector<uint32_t> before = indices;
  gi::mortonSortTriangles(positions, indices);
  std::vector<uint32_t> a = before, b = indices;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_NE(before, indices);
  // Triangles stay whole: each consecutive triple is one original triangle.
  for (size_t t = 0; t < 30; ++t) {
    EXPECT_EQ(indices[3 * t] % 3, 0u);
    EXPECT_EQ(indices[3 * t + 1], indices[3 * t] + 1);
  }
  // Sorted input stays as it is (an engine may sort its own copy first).
  std::vector<uint32_t> again = indices;
  gi::mortonSortTriangles(positions, again);
  EXPECT_EQ(again, indices);
}

TEST(ImageIo, PfmAndExrRoundTripExactly) {
  engine::FloatImage img(5, 3, 3);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i) * 0.37f - 2.0f;
  img.at(4, 2, 1) = 1e6f;
  std::string dir = std::filesystem::temp_directory_path();
  for (const char* ext : {".pfm", ".exr"}) {
    std::string path = dir + "/gi_roundtrip" + ext, error;
    ASSERT_TRUE(engine::writeImage(path, img, error)) << error;
    engine::FloatImage back;
    ASSERT_TRUE(engine::readImage(path, back, error)) << error;
    EXPECT_EQ(back.width, 5u);
    EXPECT_EQ(back.height, 3u);
    EXPECT_EQ(back.pixels, img.pixels) << ext;
  }
  std::string error;
  EXPECT_FALSE(engine::writeImage(dir + "/x.bmp", img, error));
  EXPECT_NE(error.find("x.bmp"), std::string::npos);
  engine::FloatImage back;
  EXPECT_FALSE(engine::readImage(dir + "/does_not_exist.pfm", back, error));
}

TEST(ImageIo, SrgbEncodingHandlesEdges) {
  EXPECT_EQ(engine::linearToSrgb(0.0f), 0.0f);
  EXPECT_EQ(engine::linearToSrgb(1.0f), 1.0f);
  EXPECT_EQ(engine::linearToSrgb(1e9f), 1.0f);
  EXPECT_EQ(engine::linearToSrgb(std::nanf("")), 0.0f);
  EXPECT_NEAR(engine::linearToSrgb(0.18f), 0.4613f, 1e-3f);
}

TEST(Camera, ProjectionAndRayGenerationAgree) {
  engine::Camera cam;
  cam.yfov = 0.8f;
  cam.znear = 0.1f;
  cam.worldFromView = glm::inverse(glm::lookAt(glm::vec3(1, 2, 3), glm::vec3(0), glm::vec3(0, 1, 0)));
  gpu::GpuCamera g = engine::makeGpuCamera(cam, 200, 100, nullptr);
  // A world point straight ahead, and one up-right of it, project where camera.glsl's rays go.
  glm::vec3 ahead = g.position + glm::vec3(cam.worldFromView * glm::vec4(0, 0, -5, 0));
  glm::vec4 clip = g.clipFromWorld * glm::vec4(ahead, 1.0f);
  EXPECT_NEAR(clip.x / clip.w, 0.0f, 1e-5f);
  EXPECT_NEAR(clip.y / clip.w, 0.0f, 1e-5f);
  glm::vec3 viewPoint(2.0f * g.tanHalfFovY * g.aspect, 2.0f * g.tanHalfFovY, -2.0f);  // top-right corner at depth 2
  glm::vec4 c2 = g.clipFromWorld * (cam.worldFromView * glm::vec4(viewPoint, 1.0f));
  EXPECT_NEAR(c2.x / c2.w, 1.0f, 1e-5f);   // right edge
  EXPECT_NEAR(c2.y / c2.w, -1.0f, 1e-5f);  // Vulkan: top row has y = −1
  // Reversed Z: 1 at the near plane, falling towards 0 with distance.
  float z = c2.z / c2.w;
  EXPECT_GT(z, 0.0f);
  EXPECT_LT(z, 1.0f);
  glm::vec4 nearPoint = g.clipFromWorld * (cam.worldFromView * glm::vec4(0, 0, -cam.znear, 1.0f));
  EXPECT_NEAR(nearPoint.z / nearPoint.w, 1.0f, 1e-6f);
  glm::vec4 far = g.clipFromWorld * (cam.worldFromView * glm::vec4(0, 0, -1e5f, 1.0f));
  EXPECT_GT(far.z / far.w, 0.0f);
  EXPECT_LT(far.z / far.w, z);
}

// The scene animation: a point light circles and comes back after a loop, a
// directional light's direction turns (half a loop: the opposite azimuth), the
// object turns about its own centre, and nothing else moves.
TEST(SceneAnimation, LightsAndObjectMoveOnClosedPaths) {
  engine::Scene scene;
  scene.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {0.2f, 0, 0.2f}, {0.4f, 0, 0.2f}, {0.4f, 0.2f, 0.2f}};
  scene.primitives = {{0, 3, 0, 3, 0}, {0, 3, 3, 3, 0}};
  scene.meshes = {{"floor", 0, 1}, {"box", 1, 1}};
  scene.materials.resize(1);
  scene.instances = {{"floor", 0, glm::mat4(1.0f)}, {"small_box", 1, glm::mat4(1.0f)}};
  engine::PunctualLight sun;
  sun.type = engine::LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(1, -1, 0));
  scene.lights = {sun};
  engine::SceneAnimation a = engine::makeSceneAnimation(scene);
  ASSERT_EQ(a.punctualLight, 0);
  ASSERT_EQ(a.objectInstance, 1);
  engine::animateScene(a, 0.5f * a.periodSeconds, scene);
  EXPECT_NEAR(scene.lights[0].direction.x, -sun.direction.x, 1e-5f);  // half a turn
  EXPECT_NEAR(scene.lights[0].direction.y, sun.direction.y, 1e-5f);
  EXPECT_EQ(scene.instances[0].worldFromObject, glm::mat4(1.0f));
  glm::vec3 centre(0.3f, 0.1f, 0.2f);
  glm::vec3 moved = glm::vec3(scene.instances[1].worldFromObject * glm::vec4(centre, 1.0f));
  EXPECT_NEAR(glm::length(moved - centre), 0.0f, 1e-5f) << "the object turns about its own centre";
  engine::animateScene(a, a.periodSeconds, scene);
  EXPECT_NEAR(glm::length(scene.lights[0].direction - sun.direction), 0.0f, 1e-5f);
}

// Bauszat et al. eqs. 3–5 use the norm ‖N_a − N_i‖ (not its square). With
// normal distances (0.5, 0.1, 1, 1) and depth distances (0.2, 0.55, 1, 1) the
// norm picks guide 1 (0.9 · 0.45 = 0.405 against 0.5 · 0.8 = 0.4), the squared
// distance would pick guide 0 (0.99 · 0.45 = 0.446 against 0.75 · 0.8 = 0.6).
TEST(GuidedFilterLookup, MostSimilarGuideUsesTheNormOfTheNormalDifference) {
  EXPECT_EQ(gpu::gifMostSimilarGuide(glm::vec4(0.5f, 0.1f, 1.0f, 1.0f), glm::vec4(0.2f, 0.55f, 1.0f, 1.0f)), 1);
  EXPECT_EQ(gpu::gifMostSimilarGuide(glm::vec4(1.0f, 1.0f, 1.0f, 0.1f), glm::vec4(1.0f, 1.0f, 1.0f, 0.2f)), 3);
  EXPECT_EQ(gpu::gifMostSimilarGuide(glm::vec4(0.0f), glm::vec4(0.0f)), 0);  // all alike: the first
}

TEST(DeviceNeeds, EachMissingSubgroupOperationIsNamed) {
  const VkSubgroupFeatureFlags all =
      VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  EXPECT_EQ(gi::firstMissingSubgroupSupport(VK_SHADER_STAGE_COMPUTE_BIT, all), nullptr);
  EXPECT_STREQ(gi::firstMissingSubgroupSupport(VK_SHADER_STAGE_FRAGMENT_BIT, all),
               "subgroup operations in compute shaders");
  EXPECT_STREQ(gi::firstMissingSubgroupSupport(VK_SHADER_STAGE_COMPUTE_BIT, all & ~VK_SUBGROUP_FEATURE_VOTE_BIT),
               "subgroup vote operations");
  EXPECT_STREQ(gi::firstMissingSubgroupSupport(VK_SHADER_STAGE_COMPUTE_BIT, all & ~VK_SUBGROUP_FEATURE_ARITHMETIC_BIT),
               "subgroup arithmetic operations");
  EXPECT_STREQ(gi::firstMissingSubgroupSupport(VK_SHADER_STAGE_COMPUTE_BIT, all & ~VK_SUBGROUP_FEATURE_BASIC_BIT),
               "basic subgroup operations");
}
