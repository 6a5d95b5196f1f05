// Shared fixture for GPU tests: one validated Vulkan context per test suite,
// and a check after every test that validation stayed silent.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "animation.h"
#include "camera.h"
#include "context.h"
#include "engine_or_fail.h"
#include "module_session.h"
#include "path_tracer.h"
#include "scene_gpu.h"
#include "scene_loading.h"

inline std::string sharedScene(const std::string& relative) { return std::string(GI_SHARED_SCENES) + "/" + relative; }

// The reference path tracer in tests: a failure fails the test (and the run's images are empty).
inline engine::ReferenceRun referenceOrFail(const engine::Context& c, const engine::SceneGpu& scene,
                                            const gpu::GpuCamera& camera, const engine::ReferenceSettings& settings,
                                            uint32_t spp, uint32_t samplesPerSubmit) {
  std::string error;
  engine::ReferenceRun run = engine::renderReference(c, scene, camera, settings, spp, samplesPerSubmit, error);
  if (!error.empty()) ADD_FAILURE() << error;
  return run;
}

// A scene loaded and on the device; released when it goes out of scope (a failed ASSERT included), or
// earlier by release(), or when GpuTest::load fills it again.
struct LoadedScene {
  engine::Scene scene;
  engine::SceneGpu gpu;
  const engine::Context* context = nullptr;  // set while `gpu` holds device objects

  LoadedScene() = default;
  LoadedScene(const LoadedScene&) = delete;
  LoadedScene& operator=(const LoadedScene&) = delete;
  ~LoadedScene() { release(); }
  // `scene` (loaded or built by hand) onto `c`'s device, after releasing what was there.
  template <typename... Extra>
  void upload(const engine::Context& c, Extra&&... extra) {
    release();
    std::string error;
    ASSERT_TRUE(engine::createSceneGpu(c, scene, gpu, error, std::forward<Extra>(extra)...)) << error;
    context = &c;
  }
  void release() {
    if (context) engine::destroySceneGpu(*context, gpu);
    context = nullptr;
  }
};

// The engine's scene updates in tests: a refused update fails the test (the module's error in the message).
inline void poseOrFail(const engine::Context& c, const engine::SceneAnimation& animation, float seconds,
                       engine::Scene& scene, engine::SceneGpu& gpu) {
  std::string error;
  if (!engine::poseScene(c, animation, seconds, scene, gpu, error)) ADD_FAILURE() << error;
}
inline void jumpOrFail(const engine::Context& c, const engine::SceneAnimation& animation, float seconds,
                       engine::Scene& scene, engine::SceneGpu& gpu) {
  std::string error;
  if (!engine::jumpScene(c, animation, seconds, scene, gpu, error)) ADD_FAILURE() << error;
}
inline void recordUpdateOrFail(const engine::Context& c, VkCommandBuffer cmd, const engine::Scene& scene,
                               engine::SceneGpu& gpu) {
  std::string error;
  if (!engine::recordSceneTransformUpdate(c, cmd, scene, gpu, error)) ADD_FAILURE() << error;
}
inline void recordHoldOrFail(VkCommandBuffer cmd, const engine::Scene& scene, engine::SceneGpu& gpu) {
  std::string error;
  if (!engine::recordSceneHold(cmd, scene, gpu, error)) ADD_FAILURE() << error;
}

// A module session (tools/module_session.h) released when it goes out of scope, after a failed ASSERT
// too. Declared after the scene it renders, it goes first. A session that ends holding a failure
// (ModuleSession::error: a frame, warm-up or read-back that failed) fails the test.
struct ScopedSession : tools::ModuleSession {
  const engine::Context* context;
  explicit ScopedSession(const engine::Context& c) : context(&c) {}
  ScopedSession(const ScopedSession&) = delete;
  ScopedSession& operator=(const ScopedSession&) = delete;
  ~ScopedSession() {
    EXPECT_EQ(error, "") << "the module session's first failure";
    if (module) tools::destroyModuleSession(*context, *this);  // a session destroyed by hand has no module
  }
};

class GpuTest : public ::testing::Test {
 protected:
  static engine::Context ctx;

  static void SetUpTestSuite() {
    engine::ContextDesc desc;
    desc.validation = true;
    std::string error;
    if (!engine::createContext(desc, ctx, error)) FAIL() << error;
  }
  static void TearDownTestSuite() { engine::destroyContext(ctx); }
  void TearDown() override { EXPECT_EQ(ctx.validationMessages(), 0u) << "Vulkan validation reported problems"; }

  // Loads (Morton-sorted) and uploads; fails the test on a load error (LoadedScene::release frees it early).
  // `sky`: the light beyond the scene (black by default).
  static void load(const std::string& path, LoadedScene& out, const engine::Sky& sky = {}) {
    out.release();
    out.scene = engine::Scene{};
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, out.scene, error)) << error;
    out.scene.sky = sky;
    out.upload(ctx);
  }

  static engine::ReferenceImages render(const LoadedScene& s, uint32_t width, uint32_t height,
                                        const engine::ReferenceSettings& settings, uint32_t spp) {
    gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], width, height, nullptr);
    return referenceOrFail(ctx, s.gpu, cam, settings, spp, 16).images;
  }
};

inline engine::Context GpuTest::ctx;

// A context of a test's own with validation and its synchronization checks (hazards between commands and
// across frames in flight), for the tests of frames in flight and the engine's layouts.
inline bool createSyncValidatedContext(engine::Context& ctx, std::string& error) {
  engine::ContextDesc desc;
  desc.validation = true;
  desc.synchronizationValidation = true;
  return engine::createContext(desc, ctx, error);
}

// The bytes this device's driver asks for an optimally tiled 2D image with the module's screen-image
// usage: a driver may pad a 1080p image (an NVIDIA H200 pads an 8-byte one by 1.1 MB, its rows to its
// tiles; lavapipe pads nothing).
inline VkDeviceSize driverImageBytes(const engine::Context& ctx, VkExtent2D extent, VkFormat format) {
  VkImageCreateInfo image{.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                          .imageType = VK_IMAGE_TYPE_2D,
                          .format = format,
                          .extent = {extent.width, extent.height, 1},
                          .mipLevels = 1,
                          .arrayLayers = 1,
                          .samples = VK_SAMPLE_COUNT_1_BIT,
                          .tiling = VK_IMAGE_TILING_OPTIMAL,
                          .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                   VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT};
  const VkDeviceImageMemoryRequirements info{.sType = VK_STRUCTURE_TYPE_DEVICE_IMAGE_MEMORY_REQUIREMENTS,
                                             .pCreateInfo = &image};
  VkMemoryRequirements2 requirements{.sType = VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
  vkGetDeviceImageMemoryRequirements(ctx.device, &info, &requirements);
  return requirements.memoryRequirements.size;
}

// The mean over every pixel and channel (0 for an empty image).
inline double meanOf(const engine::FloatImage& img) {
  double sum = 0.0;
  for (float v : img.pixels) sum += v;
  return img.pixels.empty() ? 0.0 : sum / double(img.pixels.size());
}

inline double meanOf(const engine::FloatImage& img, uint32_t channel) {
  double sum = 0.0;
  for (uint32_t y = 0; y < img.height; ++y)
    for (uint32_t x = 0; x < img.width; ++x) sum += img.at(x, y, channel);
  return sum / (double(img.width) * img.height);
}
