// gi::ModuleDesc::checkBounds (shaders/module/bounds.glsl): every hash-map index and
// every image coordinate of set 1 checked against its size, a violation
// counted in FrameStats::boundsViolations. Every method under what strains
// indices most (a full map, a moving scene, a panning camera, an image whose
// sides are not multiples of the 8×8 groups) touches nothing outside; and
// the check itself counts what lies outside.
#include <algorithm>
#include <cstring>
#include <ostream>

#include "gi/catalogue.h"
#include "gpu_test.h"
#include "hash_grid.h"
#include "hash_stress.comp.h"
#include "shared/hash_stress.h"
#include "light_field.h"
#include "module_device.h"
#include "module_test_helpers.h"
#include "scene/scene.h"
#include "shared/gi_frame.h"

class ModuleBoundsTest : public GpuTest {};

// One test a method of the catalogue, each under ctest's time limit of its own (900 s): in one test, the
// checked variants of every method's programs took 378 s on a cold shader cache (stop 60; the longest
// method alone, aaf, 102 s).
class ModuleBoundsMethodTest : public GpuTest, public ::testing::WithParamInterface<gi::MethodInfo> {};

namespace gi {
// The test's name in ctest: EveryMethod/ModuleBoundsMethodTest.….../<method>.
void PrintTo(const MethodInfo& info, std::ostream* out) { *out << info.name; }
}  // namespace gi

// The method with its defaults, 8 frames of the Cornell box's light circling
// and a block turning while the camera pans, at 98×66; the hash methods' map at its smallest (1,024
// cells) under cells of half a pixel: full from the first frame, a probe window that finds no slot on
// every frame.
TEST_P(ModuleBoundsMethodTest, OnAFullMapAndAMovingSceneStaysInBounds) {
  const gi::Method method = GetParam().method;
  const char* name = GetParam().name;
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  const VkExtent2D size{98, 66};
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
  desc.checkBounds = true;
  gi::Settings settings;
  settings.method = method;
  settings.hpsf.capacity = 1024;
  settings.hpsf.filterWidth = 0.5f;  // cells of half a pixel: far more than the map holds
  settings.hpsf.normalBits = 6;
  {
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
    gpu::GpuCamera previous{};
    uint32_t failedInserts = 0;
    for (uint32_t f = 0; f < 8; ++f) {
      if (f == 0)
        jumpOrFail(ctx, animation, 0.0f, s.scene, s.gpu);
      else
        poseOrFail(ctx, animation, float(f) / 30.0f, s.scene, s.gpu);
      const engine::Camera c = panned(s.scene.cameras[0], 0.02f * float(7 - f));
      const gpu::GpuCamera cam = engine::makeGpuCamera(c, size.width, size.height, f > 0 ? &previous : nullptr);
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, f > 0 ? previous : cam, f);
      previous = cam;
      gi::FrameStats stats;
      ASSERT_TRUE(gi::frameStats(session.module, f, stats)) << name << " frame " << f;
      EXPECT_EQ(stats.boundsViolations, 0u) << name << " frame " << f;
      failedInserts += stats.hash.failedInserts;
    }
    if (gi::usesHashGrid(method)) {
      EXPECT_GT(failedInserts, 0u) << name << ": the map was meant to be full";
    }
  }
  jumpOrFail(ctx, animation, 0.0f, s.scene, s.gpu);
}
INSTANTIATE_TEST_SUITE_P(EveryMethod, ModuleBoundsMethodTest,
                         ::testing::ValuesIn(gi::methodCatalogue().begin(), gi::methodCatalogue().end()));

using StressPush = gpu::HgStressPush;  // hash_stress.comp's push constants

// The check bites: the hash map's own insert, told the map is four times larger than it is, reaches
// past its arrays; checked, every such index is counted and kept inside (unchecked, it would write
// past the buffer into whatever lies beside it: not run).
TEST_F(ModuleBoundsTest, AnIndexPastTheMapIsCounted) {
  gi::vk::Device dev = openModuleDevice(ctx);
  std::string error;
  engine::DescriptorSet empty = engine::createDescriptorSet(ctx, {}, error);
  VkDescriptorSetLayout gridLayout = VK_NULL_HANDLE;
  ASSERT_FALSE(gi::createHashGridLayout(dev, gridLayout));
  gi::HashGrid grid;
  ASSERT_FALSE(gi::createHashGrid(dev, gridLayout, 1024, 1, 8, 8, 1, false, grid));
  VkDescriptorSetLayout all[] = {empty.layout, empty.layout, gridLayout};
  uint32_t spec[GI_SPEC_COUNT] = {};
  spec[GI_SPEC_CHECK_BOUNDS] = 1;
  engine::ComputeProgram stress =
      engine::createComputeProgram(ctx, spv_hash_stress_comp, all, sizeof(StressPush), {64, 1}, error, spec);
  ASSERT_EQ(error, "");
  const StressPush told4096{4096, 8, 4096, 1, 0, 1, 0, 1, 0};  // insert 4,096 keys, one sample each
  VkDescriptorSet sets[] = {empty.set, empty.set, grid.set[0]};
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    gi::recordHashGridFrameStart(dev, cmd, grid, 0);
    engine::dispatch(ctx, cmd, stress, sets, {4096, 1}, told4096);
    gi::recordHashGridTelemetryCopy(dev, cmd, grid, 0);
  });
  const uint32_t outOfBounds = gi::readHashGridTelemetry(grid, 0).outOfBounds;
  std::printf("indices past a 1,024-cell map told it has 4,096 cells: %u counted\n", outOfBounds);
  EXPECT_GT(outOfBounds, 1000u);
  engine::destroyComputeProgram(ctx, stress);
  gi::destroyHashGrid(dev, grid);
  dev.fn.vkDestroyDescriptorSetLayout(dev.device, gridLayout, dev.allocator);
  engine::destroyDescriptorSet(ctx, empty);
  gi::vk::closeDevice(dev);
}

// Texture indices: Sponza's textured materials read checked find every index inside the written
// descriptors; told the scene has one texture, the same frame counts the reads past it (and keeps them
// on texture 0, which every binding has).
TEST_F(ModuleBoundsTest, ATextureIndexPastTheWrittenOnesIsCounted) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("sponza-dabrovic/sponza-dabrovic.gltf"), s));
  gi::Scene& scene = *s.gpu.scene;
  ASSERT_GT(scene.sceneConstants.textureCount, 8u) << "Sponza's materials are textured";
  const VkExtent2D size{64, 36};
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
  desc.checkBounds = true;
  gi::Settings settings;
  settings.method = gi::Method::Raw;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  auto violations = [&](uint32_t frame) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
    gi::FrameStats stats;
    EXPECT_TRUE(gi::frameStats(session.module, frame, stats));
    return stats.boundsViolations;
  };
  EXPECT_EQ(violations(0), 0u);
  const gpu::GpuSceneConstants kept = scene.sceneConstants;
  gpu::GpuSceneConstants told = kept;
  told.textureCount = 1;
  std::memcpy(scene.constants.memory.mapped, &told, sizeof(told));
  const uint32_t counted = violations(1);
  std::printf("texture reads past a scene told it has 1 texture: %u counted\n", counted);
  EXPECT_GT(counted, 1000u);
  std::memcpy(scene.constants.memory.mapped, &kept, sizeof(kept));
  EXPECT_EQ(violations(2), 0u);
}

// The reservoirs (ReservoirSettings, on by default) under a panning camera: their temporal merge reads last
// frame's reservoirs at reprojected pixels (some outside the image), their spatial merge neighbours within
// the radius (some outside), and light indices from both; checked, nothing lands outside, for a method of
// each kind of tracing pass that takes them (raw's trace, which svgf and the screen filters share; hpsf's insert;
// the n-methods' paths; AAF's samples).
TEST_F(ModuleBoundsTest, ReservoirsUnderAPanningCameraStayInBounds) {
  LoadedScene s;
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(lightField(64, "bounds_reservoirs", true), s.scene, error)) << error;
  s.upload(ctx);
  ASSERT_TRUE(gi::picksPunctualLights(s.gpu.desc));
  const VkExtent2D size{98, 66};
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
  desc.checkBounds = true;
  for (gi::Method method : {gi::Method::Raw, gi::Method::Hpsf, gi::Method::Anhpsf, gi::Method::Aaf}) {
    gi::Settings settings;
    settings.method = method;
    settings.reservoirs.neighbours = 8;
    settings.reservoirs.radius = 32.0f;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
    const std::vector<std::string> programs = gi::programNames(session.module, settings);
    EXPECT_NE(std::find(programs.begin(), programs.end(), "gi_reservoirs"), programs.end()) << gi::methodName(method);
    gpu::GpuCamera previous{};
    for (uint32_t f = 0; f < 6; ++f) {
      const engine::Camera c = panned(s.scene.cameras[0], 0.3f * float(5 - f));
      const gpu::GpuCamera cam = engine::makeGpuCamera(c, size.width, size.height, f > 0 ? &previous : nullptr);
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, f > 0 ? previous : cam, f);
      previous = cam;
      gi::FrameStats stats;
      ASSERT_TRUE(gi::frameStats(session.module, f, stats));
      EXPECT_EQ(stats.boundsViolations, 0u) << gi::methodName(method) << " frame " << f;
    }
  }
}
