// Issue 32: glTF skins and animations played. The shipped skinned bar
// (assets/make_skinned_bar.py) after N animated frames, posed on the device
// every frame (skinning.comp, gi::updateMeshVertices), renders as the same
// bar posed on the CPU by this file's own arithmetic (from the generator's
// numbers, not the engine's animation code) and loaded as a static mesh: the
// reference to its rounding, raw and hpsf within their noise. What the engine
// does not play is named in a warning.
#include <glm/gtc/matrix_transform.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "animation.h"
#include "gbuffer.h"
#include "image_io.h"
#include "metrics.h"
#include "module_test_helpers.h"

class SkinningTest : public GpuTest {};

namespace {

const std::string kBar = std::string(GI_ASSETS) + "/skinned_bar/skinned_bar.gltf";
constexpr uint32_t kSize = 48, kFrames = 16;
constexpr float kBendY = 0.8f;  // the generator's joint height and blend zone
constexpr float kBlendFrom = 0.6f, kBlendTo = 1.0f;

float smoothstep(float a, float b, float x) {
  const float t = glm::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// The bar at `seconds` (the generator's animation: 90° about +Z over the first second, linear in angle),
// posed from its bind pose and made a static mesh.
void poseBarOnCpu(engine::Scene& scene, float seconds) {
  const float angle = glm::radians(90.0f) * glm::clamp(seconds, 0.0f, 1.0f);
  const glm::mat4 bend = glm::translate(glm::mat4(1.0f), {0, kBendY, 0}) *
                         glm::rotate(glm::mat4(1.0f), angle, {0, 0, 1}) *
                         glm::translate(glm::mat4(1.0f), {0, -kBendY, 0});
  ASSERT_EQ(scene.gltf.skinnedMeshes.size(), 1u);
  engine::Mesh& mesh = scene.meshes[scene.gltf.skinnedMeshes[0].mesh];
  for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
    for (uint32_t v = scene.primitives[p].vertexOffset;
         v < scene.primitives[p].vertexOffset + scene.primitives[p].vertexCount; ++v) {
      const glm::vec3 bind = scene.gltf.bindPositions[v];
      const float w = smoothstep(kBlendFrom, kBlendTo, bind.y);
      const glm::mat4 m = (1.0f - w) * glm::mat4(1.0f) + w * bend;
      scene.positions[v] = glm::vec3(m * glm::vec4(bind, 1.0f));
      scene.normals[v] = glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * scene.gltf.bindNormals[v]);
    }
  mesh.deformable = false;
  scene.gltf = engine::SceneAnimations{};
}

struct Rendered {
  engine::ReferenceImages reference, raw, hpsf;
};

// kFrames frames of raw and hpsf from the scene's camera, the scene posed at frame f / 30 s before frame f
// when `animated`; then the reference of the last pose.
Rendered renderBar(const engine::Context& ctx, LoadedScene& s, bool animated) {
  Rendered out;
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Hpsf}) {
    gi::Settings settings;
    settings.method = method;
    ScopedSession session(ctx);
    EXPECT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, settings, session));
    if (!session.module) return out;
    for (uint32_t f = 0; f < kFrames; ++f) {
      if (animated) poseOrFail(ctx, animation, float(f) / 30.0f, s.scene, s.gpu);
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    }
    (method == gi::Method::Raw ? out.raw : out.hpsf) = tools::readModuleImages(ctx, session);
  }
  out.reference = pixelCentreReference(ctx, s, cam, 4, 256);
  return out;
}

double relativeL1(const engine::FloatImage& a, const engine::FloatImage& b) {
  double difference = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    difference += std::abs(double(a.pixels[i]) - b.pixels[i]);
    sum += std::abs(double(b.pixels[i]));
  }
  return sum > 0.0 ? difference / sum : 1.0;
}

}  // namespace

TEST_F(SkinningTest, TheBarLoadsWithItsSkinAndAnimation) {
  engine::Scene scene;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(kBar, scene, error)) << error;
  ASSERT_EQ(scene.gltf.skins.size(), 1u);
  EXPECT_EQ(scene.gltf.skins[0].joints.size(), 2u);
  ASSERT_EQ(scene.gltf.animations.size(), 1u);
  EXPECT_FLOAT_EQ(scene.gltf.animations[0].seconds, 2.0f);
  ASSERT_EQ(scene.gltf.skinnedMeshes.size(), 1u);
  EXPECT_TRUE(scene.meshes[scene.gltf.skinnedMeshes[0].mesh].deformable);
  EXPECT_TRUE(engine::makeSceneAnimation(scene).gltf) << "the file's animation plays, not the built-in one";
  // At t = 0 the bar stands straight: loaded positions are the bind pose.
  EXPECT_EQ(scene.positions, scene.gltf.bindPositions);
}

TEST_F(SkinningTest, AnimatedBarRendersAsTheBarPosedOnTheCpu) {
  LoadedScene animated, still;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(kBar, animated.scene, error)) << error;
  engine::markAnimatedInstancesMovable(engine::makeSceneAnimation(animated.scene), animated.scene);
  still.scene = animated.scene;
  ASSERT_NO_FATAL_FAILURE(poseBarOnCpu(still.scene, float(kFrames - 1) / 30.0f));
  animated.upload(ctx);
  still.upload(ctx);
  const Rendered a = renderBar(ctx, animated, true), b = renderBar(ctx, still, false);
  const double reference = relativeL1(a.reference.final, b.reference.final);
  std::printf("bar at %.3f s: reference relative L1 %.2e (animated against posed on the CPU)\n",
              float(kFrames - 1) / 30.0f, reference);
  EXPECT_LT(reference, 2e-3) << "the device's pose is the CPU's, to the rounding of a few edge pixels";
  for (auto [name, x, y] : {std::tuple{"raw", &a.raw, &b.raw}, std::tuple{"hpsf", &a.hpsf, &b.hpsf}}) {
    const double errorAnimated = metrics::mse(x->final, b.reference.final),
                 errorStill = metrics::mse(y->final, b.reference.final);
    const double meanAnimated = meanOf(x->final), meanStill = meanOf(y->final);
    std::printf("%s: MSE against the posed bar's reference, animated %.3e, still %.3e; means %.4f, %.4f\n", name,
                errorAnimated, errorStill, meanAnimated, meanStill);
    EXPECT_LT(errorAnimated, 1.5 * errorStill) << name;
    EXPECT_NEAR(meanAnimated, meanStill, 0.03 * meanStill) << name;
  }
}

// Morph targets (a primitive's "targets", an animation's "weights" channel) are named, not dropped silently.
TEST_F(SkinningTest, MorphTargetsAreNamedInAWarning) {
  std::ifstream in(kBar);
  std::stringstream text;
  text << in.rdbuf();
  std::string json = text.str();
  const std::string attributes = "\"WEIGHTS_0\": 15\n     },";
  const size_t at = json.find(attributes);
  ASSERT_NE(at, std::string::npos) << "the generator's output changed: update this test";
  json.insert(at + attributes.size(), "\n     \"targets\": [{\"POSITION\": 13}],");
  // Beside a copy of the bar's binary buffer, outside the source tree.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gi_morph_warning_test";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(std::string(GI_ASSETS) + "/skinned_bar/skinned_bar.bin", dir / "skinned_bar.bin",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string path = (dir / "morph.gltf").string();
  std::ofstream(path) << json;
  testing::internal::CaptureStderr();
  engine::Scene scene;
  std::string error;
  const bool loaded = engine::loadSceneForRendering(path, scene, error);
  const std::string warnings = testing::internal::GetCapturedStderr();
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(loaded) << error;
  EXPECT_NE(warnings.find("warning: mesh"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("has morph targets, which are not played"), std::string::npos) << warnings;
}

// The G-buffer's motion on a deforming surface: the module's scene keeps last frame's positions
// (gi::updateMeshVertices copies them before writing the new pose), so the bar's bending pixels carry
// their motion, and a pose repeated carries none. A frame without an update keeps the last motion; a
// paused animation's hold (engine::recordSceneHold: gi::holdMeshVertices, updateInstances) ends it.
TEST_F(SkinningTest, DeformingSurfacesCarryTheirMotion) {
  LoadedScene s;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(kBar, s.scene, error)) << error;
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  engine::markAnimatedInstancesMovable(animation, s.scene);
  s.upload(ctx);
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, session));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  auto motionOf = [&](uint32_t frame) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
    const std::vector<std::byte> raw =
        readbackOrFail(ctx, session.gbuffer.color[gpu::GBUFFER_MOTION], VK_IMAGE_LAYOUT_GENERAL, 4);
    std::vector<float> lengths;
    for (size_t p = 0; p < size_t(kSize) * kSize; ++p) {
      uint16_t h[2];
      std::memcpy(h, &raw[4 * p], 4);
      lengths.push_back(glm::length(glm::vec2(engine::halfToFloat(h[0]), engine::halfToFloat(h[1]))));
    }
    return lengths;
  };
  auto motionAt = [&](float seconds, uint32_t frame) {
    poseOrFail(ctx, animation, seconds, s.scene, s.gpu);
    return motionOf(frame);
  };
  auto movingPixels = [](const std::vector<float>& lengths) {
    return size_t(std::count_if(lengths.begin(), lengths.end(), [](float l) { return l > 0.5f; }));
  };
  auto largestOf = [](const std::vector<float>& lengths) { return *std::max_element(lengths.begin(), lengths.end()); };
  motionAt(0.3f, 0);
  const std::vector<float> bending = motionAt(0.4f, 1);  // 9 degrees further
  const std::vector<float> unheld = motionOf(2);         // no update: the last motion stays
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordHoldOrFail(cmd, s.scene, s.gpu); });
  const std::vector<float> held = motionOf(3);
  motionAt(0.3f, 4);
  const std::vector<float> still = motionAt(0.3f, 5);  // the same pose again
  const size_t moving = movingPixels(bending);
  std::printf(
      "bending: %zu pixels move more than half a pixel (largest %.2f px); no update: %zu; held: largest "
      "%.2e px; the pose repeated: largest %.2e px\n",
      moving, largestOf(bending), movingPixels(unheld), largestOf(held), largestOf(still));
  EXPECT_GE(moving, 10u) << "the bar's top half moves on screen";
  EXPECT_LT(moving, size_t(kSize) * kSize / 10) << "the room stands still";
  EXPECT_EQ(movingPixels(unheld), moving) << "without an update the last motion stays (what the hold is for)";
  EXPECT_LT(largestOf(held), 1e-3f) << "a held mesh has no motion";
  EXPECT_LT(largestOf(still), 1e-3f) << "a repeated pose has no motion";
}
