// The GI module's API: named errors for impossible settings, and the raw
// method's convergence to the reference as frames accumulate.
#include "gi/catalogue.h"
#include "gpu_test.h"
#include "metrics.h"
#include "module_test_helpers.h"

class ModuleTest : public GpuTest {};

TEST_F(ModuleTest, CreateRejectsImpossibleValuesWithNamedErrors) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {16, 16});
  gi::Module* m = nullptr;
  struct Case {
    const char* what;
    gi::ModuleDesc desc;
    gi::Settings settings;
    gi::ErrorCode code;
    const char* field;
  };
  std::vector<Case> cases;
  auto add = [&](const char* what, auto editDesc, auto editSettings, gi::ErrorCode code, const char* field) {
    Case c{what, desc, gi::Settings{}, code, field};
    editDesc(c.desc);
    editSettings(c.settings);
    cases.push_back(c);
  };
  auto same = [](auto&) {};
  add(
      "zero width", [](gi::ModuleDesc& d) { d.width = 0; }, same, gi::ErrorCode::ZeroSize, "desc.width");
  add(
      "huge height", [](gi::ModuleDesc& d) { d.height = 20000; }, same, gi::ErrorCode::SizeTooLarge, "desc.width");
  add(
      "no device", [](gi::ModuleDesc& d) { d.device = VK_NULL_HANDLE; }, same, gi::ErrorCode::MissingHandle,
      "desc.device");
  add(
      "no scene", [](gi::ModuleDesc& d) { d.scene.set = VK_NULL_HANDLE; }, same, gi::ErrorCode::MissingHandle,
      "desc.scene");
  add(
      "0 spp", same, [](gi::Settings& st) { st.raw.samplesPerPixel = 0; }, gi::ErrorCode::OutOfRange,
      "settings.raw.samplesPerPixel = 0");
  add(
      "65 spp", same, [](gi::Settings& st) { st.raw.samplesPerPixel = 65; }, gi::ErrorCode::OutOfRange,
      "settings.raw.samplesPerPixel = 65");
  add(
      "0 bounces", same, [](gi::Settings& st) { st.maxBounces = 0; }, gi::ErrorCode::OutOfRange,
      "settings.maxBounces = 0");
  add(
      "0 history", same, [](gi::Settings& st) { st.raw.maxAccumulatedFrames = 0; }, gi::ErrorCode::OutOfRange,
      "settings.raw.maxAccumulatedFrames");
  add(
      "bad method", same, [](gi::Settings& st) { st.method = gi::Method(77); }, gi::ErrorCode::UnknownMethod,
      "settings.method");
  add(
      "capacity 3000", same, [](gi::Settings& st) { st.hpsf.capacity = 3000; }, gi::ErrorCode::NotPowerOfTwo,
      "settings.hpsf.capacity = 3000");
  add(
      "capacity 2^22", same, [](gi::Settings& st) { st.hpsf.capacity = 1u << 22; }, gi::ErrorCode::OutOfRange,
      "settings.hpsf.capacity");
  add(
      "negative width", same, [](gi::Settings& st) { st.hpsf.filterWidth = -4.0f; }, gi::ErrorCode::OutOfRange,
      "settings.hpsf.filterWidth");
  add(
      "NaN epsilon", same, [](gi::Settings& st) { st.gif.epsilonNormal = std::nanf(""); }, gi::ErrorCode::OutOfRange,
      "settings.gif.epsilonNormal");
  add(
      "even window", same, [](gi::Settings& st) { st.sspsf.window = 8; }, gi::ErrorCode::OutOfRange,
      "settings.sspsf.window");
  add(
      "bad view", same, [](gi::Settings& st) { st.debugView = gi::DebugView(99); }, gi::ErrorCode::OutOfRange,
      "settings.debugView");
  add(
      "another gi.h", [](gi::ModuleDesc& d) { d.structSize = 8; }, same, gi::ErrorCode::VersionMismatch,
      "desc.structSize");
  add(
      "no loader", [](gi::ModuleDesc& d) { d.getInstanceProcAddr = nullptr; }, same, gi::ErrorCode::MissingHandle,
      "desc.getInstanceProcAddr");
  add(
      "0 frames in flight", [](gi::ModuleDesc& d) { d.framesInFlight = 0; }, same, gi::ErrorCode::OutOfRange,
      "desc.framesInFlight = 0");
  add(
      "5 frames in flight", [](gi::ModuleDesc& d) { d.framesInFlight = 5; }, same, gi::ErrorCode::OutOfRange,
      "desc.framesInFlight = 5");
  add(
      "max below size", [](gi::ModuleDesc& d) { d.maxWidth = d.maxHeight = 8; }, same, gi::ErrorCode::OutOfRange,
      "desc.maxWidth");
  add(
      "outputs in an attachment layout",
      [](gi::ModuleDesc& d) { d.outputLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL; }, same,
      gi::ErrorCode::OutOfRange, "desc.outputLayout = ColorAttachmentOptimal");
  add(
      "8-bit outputs", [](gi::ModuleDesc& d) { d.outputFormat = VK_FORMAT_R8G8B8A8_UNORM; }, same,
      gi::ErrorCode::UnsupportedFormat, "desc.outputFormat");
  add(
      "8-bit histories", [](gi::ModuleDesc& d) { d.historyFormat = VK_FORMAT_R8G8B8A8_UNORM; }, same,
      gi::ErrorCode::UnsupportedFormat, "desc.historyFormat");
  // The engine says what it enabled: a chain filled by gi/device.h for the scene's traversal (the
  // ray-query structs too where it is traced with ray queries), less one feature.
  const bool rayQueryScene = desc.scene.traversal == gi::Traversal::RayQuery;
  VkPhysicalDeviceRayQueryFeaturesKHR rayQueryFeatures{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR accelerationFeatures{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  accelerationFeatures.pNext = &rayQueryFeatures;
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  f13.pNext = rayQueryScene ? &accelerationFeatures : nullptr;
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.pNext = &f13;
  VkPhysicalDeviceFeatures2 enabled{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enabled.pNext = &f12;
  ASSERT_EQ(gi::enableRequiredFeatures(enabled, rayQueryScene), nullptr);
  // The same for the compute traversal alone: no ray-query structs.
  VkPhysicalDeviceVulkan13Features computeF13 = f13;
  computeF13.pNext = nullptr;
  VkPhysicalDeviceVulkan12Features computeF12 = f12;
  computeF12.pNext = &computeF13;
  VkPhysicalDeviceFeatures2 computeOnly = enabled;
  computeOnly.pNext = &computeF12;
  add(
      "all enabled", [&](gi::ModuleDesc& d) { d.enabledFeatures = &enabled; }, same, gi::ErrorCode::None, "");
  VkPhysicalDeviceVulkan12Features f12NoAtomics = f12;
  f12NoAtomics.shaderBufferInt64Atomics = VK_FALSE;
  VkPhysicalDeviceFeatures2 noAtomics = enabled;
  noAtomics.pNext = &f12NoAtomics;
  add(
      "no 64-bit atomics", [&](gi::ModuleDesc& d) { d.enabledFeatures = &noAtomics; }, same,
      gi::ErrorCode::MissingFeature, "shaderBufferInt64Atomics");
  // Ray-query traversal needs the ray-tracing features this chain does not have.
  add(
      "no ray queries",
      [&](gi::ModuleDesc& d) {
        d.enabledFeatures = &computeOnly;
        d.scene.traversal = gi::Traversal::RayQuery;
      },
      same, gi::ErrorCode::MissingFeature, "ray-query");
  for (const Case& c : cases) {
    gi::Error e = gi::create(c.desc, c.settings, m);
    EXPECT_EQ(e.code, c.code) << c.what << ": " << e.message;
    EXPECT_NE(e.message.find(c.field), std::string::npos) << c.what << ": " << e.message;
    if (c.code == gi::ErrorCode::None) {
      EXPECT_NE(m, nullptr) << c.what;
      gi::destroy(m);
      m = nullptr;
    }
    EXPECT_EQ(m, nullptr) << c.what;
  }
  EXPECT_EQ(gi::version(), uint32_t(GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR));
  // A valid module accepts valid settings and refuses invalid ones without changing.
  ASSERT_FALSE(gi::create(desc, gi::Settings{}, m));
  gi::Settings bad;
  bad.maxBounces = 100;
  EXPECT_EQ(gi::setSettings(m, bad).code, gi::ErrorCode::OutOfRange);
  gi::destroy(m);
}

TEST_F(ModuleTest, RawAccumulationConvergesToTheReference) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 24, H = 24;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 2048);

  gi::Settings settings;
  settings.maxBounces = 2;
  settings.raw.samplesPerPixel = 1;
  settings.raw.temporalAccumulation = true;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  std::vector<double> relMse;
  uint32_t frame = 0;
  for (uint32_t target : {2u, 8u, 32u, 128u}) {
    for (; frame < target; ++frame) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
    engine::ReferenceImages out = tools::readModuleImages(ctx, session);
    relMse.push_back(metrics::relMse(out.final, ref.final));
    EXPECT_EQ(gi::stats(session.module).accumulatedFrames, target);
  }
  // relMSE ∝ 1/N: each 4× more frames cuts it by about 4 (the reference's own
  // noise, 1/16 of the last step's, is the floor).
  for (size_t i = 1; i < relMse.size(); ++i) {
    double ratio = relMse[i - 1] / relMse[i];
    EXPECT_GT(ratio, 2.5) << "step " << i << ": " << relMse[i - 1] << " → " << relMse[i];
    EXPECT_LT(ratio, 6.0) << "step " << i << ": " << relMse[i - 1] << " → " << relMse[i];
  }
  // And the mean is unbiased.
  engine::ReferenceImages out = tools::readModuleImages(ctx, session);
  for (uint32_t c = 0; c < 3; ++c) EXPECT_NEAR(meanOf(out.final, c), meanOf(ref.final, c), 0.02 * meanOf(ref.final, c));
}

TEST_F(ModuleTest, RayBudgetCapsTheSampleCount) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 16, H = 16;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  gi::Settings settings;
  settings.raw.samplesPerPixel = 16;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  gi::FrameStats unlimited = gi::stats(session.module);
  EXPECT_EQ(unlimited.samplesPerPixel, 16u);
  // A budget of a quarter of what 16 spp costs gives about 4 spp.
  settings.rayBudget = unlimited.raysTraced / 4;
  ASSERT_FALSE(gi::setSettings(session.module, settings));
  for (uint32_t f = 1; f < 4; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  gi::FrameStats limited = gi::stats(session.module);
  EXPECT_GE(limited.samplesPerPixel, 3u);
  EXPECT_LE(limited.samplesPerPixel, 5u);
  EXPECT_LE(double(limited.raysTraced), 1.15 * double(settings.rayBudget));
  // A budget below one path per pixel still traces one (the floor is documented).
  settings.rayBudget = 1;
  ASSERT_FALSE(gi::setSettings(session.module, settings));
  for (uint32_t f = 4; f < 6; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  EXPECT_EQ(gi::stats(session.module).samplesPerPixel, 1u);
}

// A settings change restarts the history only where the catalogue says it makes it wrong
// (SettingInfo::restartsHistory) or the method changes; gi::invalidate(History) restarts it on request.
// FrameStats::accumulatedFrames counts the frames behind the median pixel: svgf with a still camera
// holds one more each frame.
TEST_F(ModuleTest, SettingsChangesKeepTheHistoryUnlessTheyMakeItWrong) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 16, 16, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Svgf;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {16, 16}, settings, session));
  uint32_t frame = 0;
  auto historyAfter = [&](uint32_t frames) {
    for (uint32_t f = 0; f < frames; ++f, ++frame)
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
    return gi::stats(session.module).accumulatedFrames;
  };
  EXPECT_EQ(historyAfter(6), 6u);
  struct Change {
    const char* key;
    double value;
    bool restarts;
  };
  const Change changes[] = {{"ray_budget", 2000, false},
                            {"svgf.spp", 2, false},
                            {"svgf.sigma_luminance", 8, false},
                            {"temporal.min_blend", 0.1, false},
                            {"view", 1, false},
                            {"view", 0, false},
                            {"seed", 7, false},
                            {"bounces", 2, true},
                            {"temporal.gradients", 1, true},
                            {"temporal.gradients", 0, true}};
  uint32_t expected = 6;
  for (const Change& c : changes) {
    const gi::SettingInfo* info = gi::findSetting(c.key);
    ASSERT_NE(info, nullptr) << c.key;
    EXPECT_EQ(info->restartsHistory, c.restarts) << c.key;
    info->set(settings, c.value);
    ASSERT_FALSE(gi::setSettings(session.module, settings)) << c.key;
    expected = c.restarts ? 2 : expected + 2;
    EXPECT_EQ(historyAfter(2), expected) << "after " << c.key << " = " << c.value;
  }
  gi::invalidate(session.module, gi::Invalidate::History);
  EXPECT_EQ(historyAfter(1), 1u) << "after invalidate(History)";
  settings.method = gi::Method::Sspsf;
  settings.sspsf.temporalReprojection = true;
  ASSERT_FALSE(gi::setSettings(session.module, settings));
  EXPECT_EQ(historyAfter(3), 3u) << "a new method starts over";
}

TEST_F(ModuleTest, StatsReportPassesRaysAndMemory) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 16, 16, nullptr);
  gi::Settings settings;
  settings.raw.samplesPerPixel = 2;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {16, 16}, settings, session));
  tools::FrameTiming t = tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  gi::FrameStats st = gi::stats(session.module);
  ASSERT_EQ(st.passes.size(), 2u);
  EXPECT_EQ(st.passes[0].name, "raw_trace");
  EXPECT_EQ(st.passes[1].name, "composite");
  EXPECT_GT(st.passes[0].ms, 0.0);
  EXPECT_GE(st.raysTraced, 16u * 16u * 2u);  // at least the shadow ray of every path
  EXPECT_GE(st.memoryBytes, 5u * 16u * 16u * 16u);
  EXPECT_EQ(t.passes.front().name, "gbuffer");
}

// Every method and every debug view records cleanly under validation and
// produces finite pixels.
TEST_F(ModuleTest, EveryMethodAndDebugViewRunsAndStaysFinite) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 24, H = 16;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  gi::Settings settings;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  uint32_t frame = 0;
  auto check = [&](const char* what) {
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame++);
    engine::ReferenceImages out = tools::readModuleImages(ctx, session);
    for (const engine::FloatImage* img : {&out.final, &out.direct, &out.indirect})
      for (float v : img->pixels) ASSERT_TRUE(std::isfinite(v)) << what;
    double sum = 0.0;
    for (float v : out.final.pixels) sum += v;
    EXPECT_GT(sum, 0.0) << what << ": the lit Cornell box cannot be black";
  };
  // Every method of the catalogue with its defaults.
  for (const gi::MethodInfo& info : gi::methodCatalogue()) {
    settings = gi::Settings{};
    settings.method = info.method;
    ASSERT_FALSE(gi::setSettings(session.module, settings));
    check(info.name);
  }
  settings = gi::Settings{};
  settings.method = gi::Method::Gif;
  settings.gif.supersamples = 2;
  for (uint32_t dims : {1u, 3u}) {
    settings.gif.guidanceDimensions = dims;
    ASSERT_FALSE(gi::setSettings(session.module, settings));
    check("gif supersampled, fewer guidance dimensions");
  }
  // Every debug view of the catalogue, on a method that fills it. Views of light must show some; the
  // others are pictures scaled for display (a count past its scale reads above 1) that may be black
  // in places: finite and not negative.
  auto methodShowing = [](gi::DebugView v) {
    if (v >= gi::DebugView::AafZMin && v <= gi::DebugView::AafFilterWidth) return gi::Method::Aaf;
    if (v >= gi::DebugView::HashCells && v <= gi::DebugView::ContinuationDepth) return gi::Method::Anhpsf;
    if (v == gi::DebugView::SvgfVariance || v == gi::DebugView::TemporalGradient) return gi::Method::Svgf;
    return gi::Method::Gif;
  };
  for (const gi::DebugViewInfo& view : gi::debugViewCatalogue()) {
    settings = gi::Settings{};
    settings.method = methodShowing(view.view);
    settings.debugView = view.view;
    settings.temporal.gradients = view.view == gi::DebugView::TemporalGradient;
    ASSERT_FALSE(gi::setSettings(session.module, settings)) << view.name;
    if (view.radiance) {
      check(view.name);
      continue;
    }
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame++);
    for (float v : tools::readModuleImages(ctx, session).final.pixels)
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << view.name << ": " << v;
  }
}

// Mehta et al. Fig. 10: raising μ narrows the filters and raises the sample
// counts, so the error against the reference falls.
TEST_F(ModuleTest, AafErrorFallsAsMuGrows) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 32, H = 32;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  engine::ReferenceImages ref = pixelCentreReference(ctx, s, cam, 2, 2048);
  gi::Settings settings;
  settings.method = gi::Method::Aaf;
  settings.maxBounces = 2;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
  std::vector<double> errors;
  std::vector<uint32_t> spp;
  uint32_t frame = 0;
  for (float mu : {0.5f, 1.0f, 2.0f, 4.0f}) {
    settings.aaf.mu = mu;
    ASSERT_FALSE(gi::setSettings(session.module, settings));
    double e = 0.0;
    for (int k = 0; k < 2; ++k) {  // two frames: an error estimate with less luck in it
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame++);
      e += metrics::mse(tools::readModuleImages(ctx, session).indirect, ref.indirect) / 2.0;
    }
    errors.push_back(e);
    spp.push_back(gi::stats(session.module).samplesPerPixel);
  }
  for (size_t i = 1; i < errors.size(); ++i) {
    EXPECT_LT(errors[i], errors[i - 1]) << "mu step " << i;
    EXPECT_GE(spp[i], spp[i - 1]) << "mu step " << i;
  }
}

TEST_F(ModuleTest, AmbientOcclusionIsInUnitRangeAndOneOverAnOpenPlane) {
  for (const char* path : {"pointlight-plane/pointlight_plane.gltf", "cornell-box-mcguire/CornellBox-Original.gltf"}) {
    LoadedScene s;
    load(sharedScene(path), s);
    gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 24, 24, nullptr);
    gi::Settings settings;
    settings.method = gi::Method::AafAo;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {24, 24}, settings, session));
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    engine::ReferenceImages out = tools::readModuleImages(ctx, session);
    bool open = std::string(path).find("plane") != std::string::npos;
    double mean = 0.0;
    for (float v : out.final.pixels) {
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
      if (open) {
        ASSERT_EQ(v, 1.0f) << "nothing above the plane occludes it";
      }
      mean += v / double(out.final.pixels.size());
    }
    if (!open) {
      EXPECT_LT(mean, 0.9) << "inside the box, walls occlude";
    }
  }
}

// NaN and Inf arriving in the G-buffer stop at the module boundary: the pixels
// count as background, are reported in the stats, and do not poison history.
TEST_F(ModuleTest, NonFiniteGBufferValuesDoNotSpread) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 24, H = 24;
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
  // Every method; raw with history and the hash methods with their caches are where a NaN could persist.
  for (const gi::MethodInfo& info : gi::methodCatalogue()) {
    const gi::Method method = info.method;
    gi::Settings settings;
    settings.method = method;
    settings.raw.temporalAccumulation = true;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {W, H}, settings, session));
    const engine::GBuffer& g = session.gbuffer;
    const gi::GBufferViews views = tools::gbufferViews(g);
    for (uint32_t frame = 0; frame < 3; ++frame) {
      submitOrFail(ctx, [&](VkCommandBuffer cmd) {
        engine::recordGBuffer(ctx, cmd, session.gbufferPass, s.scene, s.gpu, session.gbuffer, cam, nullptr);
        if (frame == 1) {  // frame 1: the engine hands over NaN depths and infinite emission
          VkClearColorValue nan{{std::nanf(""), 0, 0, 0}}, inf{{INFINITY, INFINITY, INFINITY, 1}};
          VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
          vkCmdClearColorImage(cmd, g.color[gpu::GBUFFER_VIEWZ].image, VK_IMAGE_LAYOUT_GENERAL, &nan, 1, &range);
          vkCmdClearColorImage(cmd, g.color[gpu::GBUFFER_EMISSION].image, VK_IMAGE_LAYOUT_GENERAL, &inf, 1, &range);
          engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
        }
        gi::recordFrame(session.module, cmd, {views, engine::moduleCamera(cam), engine::moduleCamera(cam), frame});
        engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                              VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
      });
      gi::FrameStats st = gi::stats(session.module);
      engine::ReferenceImages out = tools::readModuleImages(ctx, session);
      double sum = 0.0;
      for (const engine::FloatImage* img : {&out.final, &out.direct, &out.indirect})
        for (float v : img->pixels) {
          ASSERT_TRUE(std::isfinite(v)) << gi::methodName(method) << " frame " << frame;
          sum += v;
        }
      if (frame == 1) {
        EXPECT_GE(st.sanitized, W * H / 2) << gi::methodName(method) << ": the covered pixels were dropped and counted";
      } else {
        EXPECT_GT(sum, 0.0) << gi::methodName(method) << " frame " << frame << " recovers";
      }
    }
  }
}
