// The scene changing under a live module (gi::setScene): an emissive mesh
// streamed in after create is lit without recreating the module.
#include "module_test_helpers.h"
#include "procedural_scene.h"

class ModuleSceneTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 32;

// A closed-ish room (floor, ceiling, three walls); with `lamp`, an emissive
// panel under the ceiling. Without it nothing in the room emits.
std::string room(bool lamp, const std::string& name) {
  testscene::Description d;
  d.quads.push_back({{{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}}, glm::vec3(0.6f)});    // floor
  d.quads.push_back({{{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}}, glm::vec3(0.6f)});    // ceiling
  d.quads.push_back({{{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, glm::vec3(0.6f)});  // back
  d.quads.push_back({{{-1, 0, 1}, {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}}, glm::vec3(0.7f, 0.2f, 0.2f)});
  d.quads.push_back({{{1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}}, glm::vec3(0.2f, 0.7f, 0.2f)});
  if (lamp) {
    testscene::Quad panel{{{-0.3f, 1.98f, -0.3f}, {0.3f, 1.98f, -0.3f}, {0.3f, 1.98f, 0.3f}, {-0.3f, 1.98f, 0.3f}}};
    panel.albedo = glm::vec3(0.0f);
    panel.emission = glm::vec3(8.0f);
    // These corners run counter-clockwise seen from below: it shines down.
    d.quads.push_back(panel);
  }
  d.eye = {0, 1, 2.6f};
  d.target = {0, 0.8f, 0};
  return testscene::write(d, name);
}

}  // namespace

// Created on the dark room, then handed the room with a lamp (a new set 0,
// hasEmissiveTriangles now true): the programs are rebuilt with emissive
// sampling, and the frames match a module created on the lit room from the
// start, frame for frame (same seed, same frame indices).
TEST_F(ModuleSceneTest, EmissiveMeshAddedAfterCreateIsLit) {
  LoadedScene dark, lit;
  ASSERT_NO_FATAL_FAILURE(load(room(false, "scene_dark_room"), dark));
  ASSERT_NO_FATAL_FAILURE(load(room(true, "scene_lit_room"), lit));
  ASSERT_FALSE(dark.gpu.hasEmissiveTriangles());
  ASSERT_TRUE(lit.gpu.hasEmissiveTriangles());
  const gpu::GpuCamera cam = engine::makeGpuCamera(lit.scene.cameras[0], kSize, kSize, nullptr);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Atrous, gi::Method::Hpsf}) {
    gi::Settings settings;
    settings.method = method;
    ScopedSession streamed(ctx), fresh(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, dark, {kSize, kSize}, settings, streamed));
    for (uint32_t f = 0; f < 2; ++f) tools::renderModuleFrame(ctx, streamed, dark.scene, dark.gpu, cam, cam, f);
    EXPECT_EQ(meanOf(tools::readModuleImages(ctx, streamed).final), 0.0)
        << gi::methodName(method) << ": nothing emits yet";
    // The lamp streams in: the engine's new set 0 and its facts.
    ASSERT_FALSE(gi::setScene(streamed.module, tools::sceneDesc(lit.gpu)));
    gi::invalidate(streamed.module, gi::Invalidate::All);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, lit, {kSize, kSize}, settings, fresh));
    streamed.preExposure = fresh.preExposure;  // the same exposure: the same half-float rounding
    for (uint32_t f = 2; f < 5; ++f) {
      tools::renderModuleFrame(ctx, streamed, lit.scene, lit.gpu, cam, cam, f);
      tools::renderModuleFrame(ctx, fresh, lit.scene, lit.gpu, cam, cam, f);
    }
    const engine::FloatImage a = tools::readModuleImages(ctx, streamed).final;
    const engine::FloatImage b = tools::readModuleImages(ctx, fresh).final;
    EXPECT_GT(meanOf(a), 0.01) << gi::methodName(method) << ": lit";
    size_t differ = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != b.pixels[i];
    EXPECT_EQ(differ, 0u) << gi::methodName(method) << ": the streamed module's frame differs from a fresh one's";
  }
}

// A bad scene is a named error and the module goes on with the old one.
TEST_F(ModuleSceneTest, BadSceneIsANamedErrorAndKeepsTheOldOne) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(room(true, "scene_bad_update"), s));
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, session));
  gi::SceneDesc bad = tools::sceneDesc(s.gpu);
  bad.set = VK_NULL_HANDLE;
  gi::Error e = gi::setScene(session.module, bad);
  EXPECT_EQ(e.code, gi::ErrorCode::MissingHandle);
  EXPECT_NE(e.message.find("gi::setScene scene.layout"), std::string::npos) << e.message;
  bad = tools::sceneDesc(s.gpu);
  bad.typicalRadiance = -1.0f;
  EXPECT_EQ(gi::setScene(session.module, bad).code, gi::ErrorCode::OutOfRange);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  EXPECT_GT(meanOf(tools::readModuleImages(ctx, session).final), 0.01);
}
