// gi-render: headless rendering of a glTF scene with the reference path tracer
// (and, through the GI module, the real-time methods), writing one AOV and a
// JSON record of what it cost.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "camera.h"
#include "image_io.h"
#include "metrics.h"
#include "cli.h"
#include "bench_configs.h"
#include "module_session.h"
#include "settings_keys.h"
#include "context.h"
#include "path_tracer.h"
#include "scene_gpu.h"
#include "scene_loading.h"
#include "animation.h"
#include "window.h"

namespace {

const std::string kMethodHelp = "reference (default) or a GI module method: " + tools::methodList();
const cli::Option kOptions[] = {
    {"scene", "FILE.gltf", "scene to render (required)"},
    {"size", "WxH", "image size in pixels (default 320x180)"},
    {"dynamic-resolution", "WxH", "module methods: the render size alternates between --size and this one every "
                                  "4 frames (starting at --size), in the same images (gi::resize within "
                                  "ModuleDesc::maxWidth x maxHeight); the last frame is written at its size"},
    {"camera", "N", "glTF camera index (default 0; a default camera is made when the file has none)"},
    {"method", "NAME", kMethodHelp.c_str()},
    {"set", "KEY=V", "a GI module setting, repeatable (keys: see --help)"},
    {"spp", "N", "samples per pixel per frame (default: 64 for the reference, the method's own default for a module method)"},
    {"frames", "N", "frames to accumulate (default 1); total samples = spp × frames"},
    {"max-bounces", "B", "indirect bounces, 0 = direct light only (default 4)"},
    {"seed", "S", "random seed (default 1); the same seed gives the same image"},
    {"aov", "NAME", "final|direct|indirect|albedo|normal|depth (default final)"},
    {"out", "FILE", "output image: .exr or .pfm (linear) or .png (sRGB)"},
    {"stats", "FILE.json", "write device, timings (each program's first dispatch apart), rays and wall time as JSON"},
    {"compare", "REF.exr", "the written image's MSE against this one (same size), printed and in --stats as "
                           "mse_vs_reference"},
    {"pixel-centres", nullptr, "the reference traces through pixel centres, as the module's G-buffer sees them "
                               "(default: jittered within each pixel)"},
    {"validation", nullptr, "enable Vulkan validation; any message makes the run fail"},
    {"check-bounds", nullptr, "module methods: check every hash-map index and image coordinate the module's "
                              "passes use (gi::ModuleDesc::checkBounds); any outside makes the run fail"},
    cli::kTraversalOption,
    cli::kSkyOption,
    cli::kPointLightsOption,
    cli::kLightSamplerOption,
    cli::kLightTreeCutOption,
    {"window", nullptr, "show the frames in a GLFW window (module methods; needs a display)"},
    {"animate", nullptr, "the light and an object move, 30 frames a second (engine/animation.h); the reference "
                         "renders the last frame's pose"},
    {"help", nullptr, "show this message"},
};
const char* const kAovs[] = {"final", "direct", "indirect", "albedo", "normal", "depth"};
const char* kSynopsis = "--scene FILE.gltf [options]";

int usageError(const std::string& message) {
  std::fprintf(stderr, "gi-render: %s\n%s", message.c_str(), cli::usage("gi-render", kSynopsis, kOptions).c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  auto wallStart = std::chrono::steady_clock::now();
  cli::Args args;
  std::string error;
  if (!cli::parse(argc, argv, kOptions, args, error)) return usageError(error);
  if (args.has("help")) {
    std::printf("%s\nmodule settings for --set:\n", cli::usage("gi-render", kSynopsis, kOptions).c_str());
    for (const std::string& k : tools::settingKeys()) std::printf("  %s\n", k.c_str());
    std::printf("debug views for --set view=N:\n");
    for (const std::string& v : tools::debugViewLines()) std::printf("  %s\n", v.c_str());
    return 0;
  }
  if (!args.has("scene")) return usageError("--scene is required");
  uint32_t width, height, cameraIndex, spp, frames, bounces, seed;
  std::vector<const char*> methodChoices = tools::methodNames();
  methodChoices.insert(methodChoices.begin(), "reference");
  std::string method, aov;
  if (!cli::getSize(args, "size", 320, 180, width, height, error) ||
      !cli::getUint(args, "camera", 0, 0, 1u << 20, cameraIndex, error) ||
      !cli::getUint(args, "spp", 64, 1, 1u << 20, spp, error) ||
      !cli::getUint(args, "frames", 1, 1, 1u << 20, frames, error) ||
      !cli::getUint(args, "max-bounces", 4, 0, 1024, bounces, error) ||
      !cli::getUint(args, "seed", 1, 0, UINT32_MAX, seed, error) ||
      !cli::getChoice(args, "method", "reference", methodChoices, method, error) ||
      !cli::getChoice(args, "aov", "final", kAovs, aov, error))
    return usageError(error);
  if (uint64_t(spp) * frames > (1u << 24)) return usageError("spp × frames must not exceed 16777216");
  // --dynamic-resolution: frame f renders at renderSize(f).
  uint32_t alternateWidth = 0, alternateHeight = 0;
  const bool dynamicResolution = args.has("dynamic-resolution");
  if (dynamicResolution && !cli::getSize(args, "dynamic-resolution", 0, 0, alternateWidth, alternateHeight, error))
    return usageError(error);
  if (dynamicResolution && (method == "reference" || args.has("window")))
    return usageError("--dynamic-resolution is for module methods without --window");
  auto renderSize = [&](uint32_t f) {
    return dynamicResolution && (f / 4) % 2 == 1 ? VkExtent2D{alternateWidth, alternateHeight} : VkExtent2D{width, height};
  };
  engine::Traversal traversal = engine::Traversal::Auto;
  if (!cli::getTraversal(args, traversal, error)) return usageError(error);
  uint32_t lightSampler = 2, lightTreeCut = 4;  // SceneCreateDesc's defaults (gpu::LIGHT_SAMPLER_TREE)
  if (!cli::getLightSampler(args, lightSampler, lightTreeCut, error)) return usageError(error);
  engine::Sky sky;
  if (!cli::getSky(args, sky, error)) return usageError(error);
  gi::Settings moduleSettings;
  if (method != "reference") {
    gi::methodFromName(method, moduleSettings.method);
    moduleSettings.maxBounces = bounces;
    moduleSettings.seed = seed;
    if (args.has("spp")) tools::setSamplesPerPixel(moduleSettings, spp);
    moduleSettings.raw.temporalAccumulation = frames > 1;  // a static camera: average the frames
    if (args.has("set"))
      for (const std::string& assignment : cli::splitList(args.values["set"]))
        if (!tools::applySetting(moduleSettings, assignment, error)) return usageError(error);
    if (gi::Error e = gi::validate(moduleSettings)) return usageError(e.message);
    spp = tools::samplesPerPixel(moduleSettings);  // without --spp: the method's default, not the reference's 64
  }

  engine::Scene scene;
  if (!engine::loadSceneForRendering(args.values["scene"], scene, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  if (!cli::applyPointLights(args, scene, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  scene.lightSampler = lightSampler;
  scene.lightTreeCut = lightTreeCut;
  if (cameraIndex >= scene.cameras.size()) {
    std::fprintf(stderr, "gi-render: %s: camera %u does not exist (the scene has %zu)\n", scene.sourcePath.c_str(),
                 cameraIndex, scene.cameras.size());
    return 1;
  }

  engine::ContextDesc desc;
  desc.validation = args.has("validation") || std::getenv("GI_VALIDATION") != nullptr;
  desc.traversal = traversal;
  bool windowed = args.has("window");
  if (windowed && method == "reference") return usageError("--window shows module methods (raw, gif, ...), not the reference");
  if (windowed) {
    if (!engine::windowInstanceExtensions(desc.instanceExtensions, error)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      return 1;
    }
    desc.swapchain = true;
  }
  engine::Context ctx;
  if (!engine::createContext(desc, ctx, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  engine::SceneGpu sceneGpu;
  scene.sky = std::move(sky);
  // --animate: the scene's pose for frame f, uploaded before the frame is recorded.
  const bool animate = args.has("animate");
  const engine::SceneAnimation animation = engine::makeSceneAnimation(scene);
  if (animate) engine::markAnimatedInstancesMovable(animation, scene);
  engine::createSceneGpu(ctx, scene, sceneGpu);
  gpu::GpuCamera camera = engine::makeGpuCamera(scene.cameras[cameraIndex], width, height, nullptr);
  auto poseFor = [&](uint32_t f) {
    if (!animate) return;
    engine::poseScene(ctx, animation, float(f) / 30.0f, scene, sceneGpu);
  };

  engine::ReferenceRun run;
  std::map<std::string, double> passMs;  // summed over frames
  gi::FrameStats::Hash lastHash;        // module methods: the last frame's hash telemetry
  uint32_t tracedSpp = spp;              // module methods: what the last frame traced (AAF: its adaptive mean)
  uint64_t memoryBytes = 0;              // module methods: device memory the module held after the last frame
  uint64_t memoryUsedBytes = 0;          // of that, what its buffers and images occupy
  uint64_t memoryTransientBytes = 0;     // of that, images whose contents live within one frame
  uint32_t deviceAllocations = 0;
  gi::MemoryPrediction predicted;        // module methods: gi::predictMemory before the module was created
  uint64_t firstFrameMemoryBytes = 0;    // module methods: held after the first frame (dynamic resolution: constant)
  int status = 0;
  uint64_t boundsViolations = 0;         // module methods with --check-bounds: summed over the frames
  // Each program's first dispatch, before any timed frame (the compile, on lavapipe).
  std::map<std::string, double> firstDispatchMs;
  if (method == "reference") {
    engine::ReferenceSettings settings;
    settings.maxBounces = bounces;
    settings.seed = seed;
    settings.pixelJitter = !args.has("pixel-centres");
    poseFor(frames - 1);
    run = engine::renderReference(ctx, sceneGpu, camera, settings, spp * frames);
    passMs["path_trace"] = run.gpuMs;
    firstDispatchMs["path_trace"] = run.firstDispatchMs;
  } else {
    tools::ModuleSession session;
    gi::ModuleDesc moduleDesc = tools::moduleDesc(ctx, sceneGpu, {width, height});
    moduleDesc.checkBounds = args.has("check-bounds");
    moduleDesc.maxWidth = std::max(width, alternateWidth);  // dynamic resolution: every image at the larger size
    moduleDesc.maxHeight = std::max(height, alternateHeight);
    if (gi::Error e = gi::predictMemory(moduleDesc, moduleSettings, predicted)) {
      std::fprintf(stderr, "gi-render: %s\n", e.message.c_str());
      engine::destroySceneGpu(ctx, sceneGpu);
      engine::destroyContext(ctx);
      return 2;
    }
    if (!tools::createModuleSession(ctx, sceneGpu, {width, height}, moduleSettings, session, error, &moduleDesc)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      engine::destroySceneGpu(ctx, sceneGpu);
      engine::destroyContext(ctx);
      return 2;
    }
    for (const tools::ProgramWarmup& w : tools::warmModulePrograms(ctx, session, moduleSettings, scene, sceneGpu, camera))
      firstDispatchMs[w.name] = w.ms;
    engine::Window window;
    if (windowed && !engine::createWindow(ctx, width, height, "gi-render", window, error)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      tools::destroyModuleSession(ctx, session);
      engine::destroySceneGpu(ctx, sceneGpu);
      engine::destroyContext(ctx);
      return 1;
    }
    for (uint32_t f = 0; f < frames; ++f) {
      if (windowed) {
        // Windowed: the same frame script into the window's command buffer, then present.
        uint32_t image = 0;
        if (engine::windowShouldClose(window)) break;
        if (!engine::beginWindowFrame(ctx, window, image)) continue;
        if (animate) {
          engine::animateScene(animation, float(f) / 30.0f, scene);
          engine::recordSceneTransformUpdate(ctx, window.cmd, scene, sceneGpu);
        }
        tools::recordModuleFrame(ctx, window.cmd, session, scene, sceneGpu, camera, camera, f);
        engine::endWindowFrame(ctx, window, image, gi::outputs(session.module).composite, {width, height});
        continue;
      }
      poseFor(f);
      if (const VkExtent2D size = renderSize(f); size.width != session.extent.width || size.height != session.extent.height) {
        if (!tools::resizeModuleSession(ctx, session, size, error)) {
          std::fprintf(stderr, "gi-render: %s\n", error.c_str());
          status = 1;
          break;
        }
        camera = engine::makeGpuCamera(scene.cameras[cameraIndex], size.width, size.height, nullptr);
      }
      tools::FrameTiming t = tools::renderModuleFrame(ctx, session, scene, sceneGpu, camera, camera, f);
      if (f == 0) firstFrameMemoryBytes = gi::stats(session.module).memoryBytes;
      boundsViolations += gi::stats(session.module).boundsViolations;
      for (const gi::PassTiming& p : t.passes) passMs[p.name] += p.ms;
      run.gpuMs += t.totalMs;
      run.rays += t.rays;
    }
    if (windowed) engine::destroyWindow(ctx, window);
    run.images = tools::readModuleImages(ctx, session);
    width = session.extent.width;  // the last frame's size (--dynamic-resolution)
    height = session.extent.height;
    const gi::FrameStats last = gi::stats(session.module);
    tracedSpp = last.samplesPerPixel;
    lastHash = last.hash;
    memoryBytes = last.memoryBytes;
    memoryUsedBytes = last.memoryUsedBytes;
    memoryTransientBytes = last.memoryTransientBytes;
    deviceAllocations = last.deviceAllocations;
    tools::destroyModuleSession(ctx, session);
  }

  if (boundsViolations > 0) {
    std::fprintf(stderr, "gi-render: %llu accesses outside a buffer or image (--check-bounds)\n",
                 static_cast<unsigned long long>(boundsViolations));
    status = 1;
  }
  if (args.has("out")) {
    const engine::ReferenceImages& im = run.images;
    const engine::FloatImage& img = aov == "direct" ? im.direct
                                    : aov == "indirect" ? im.indirect
                                    : aov == "albedo"   ? im.albedo
                                    : aov == "normal"   ? im.normal
                                    : aov == "depth"    ? im.depth
                                                        : im.final;
    if (!engine::writeImage(args.values["out"], img, error)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      status = 1;
    }
  }
  double mseVsReference = -1.0;  // --compare
  if (args.has("compare")) {
    const engine::ReferenceImages& im = run.images;
    const engine::FloatImage& img = aov == "direct" ? im.direct : aov == "indirect" ? im.indirect : im.final;
    engine::FloatImage reference;
    if (!engine::readImage(args.values["compare"], reference, error)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      status = 1;
    } else if (reference.width != img.width || reference.height != img.height) {
      std::fprintf(stderr, "gi-render: %s is %ux%u, the image %ux%u\n", args.values["compare"].c_str(), reference.width,
                   reference.height, img.width, img.height);
      status = 1;
    } else {
      mseVsReference = metrics::mse(img, reference);
      std::printf("MSE against %s: %.4e\n", args.values["compare"].c_str(), mseVsReference);
    }
  }

  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  double mraysPerSecond = run.gpuMs > 0.0 ? double(run.rays) / (run.gpuMs * 1e3) : 0.0;
  std::printf("%s: %ux%u, %u spp, B=%u on %s (%s traversal): %.1f ms GPU, %llu rays (%.3f Mrays/s), %.2f s wall\n",
              scene.sourcePath.c_str(), width, height, spp * frames, bounces, ctx.properties.deviceName,
              engine::traversalName(ctx.traversal), run.gpuMs,
              (unsigned long long)run.rays, mraysPerSecond, wall);
  if (args.has("stats")) {
    nlohmann::json j;
    j["device"] = ctx.properties.deviceName;
    j["traversal"] = engine::traversalName(ctx.traversal);
    j["scene"] = scene.sourcePath;
    j["method"] = method;
    j["width"] = width;
    j["height"] = height;
    j["spp"] = spp * frames;
    j["frames"] = frames;
    j["max_bounces"] = bounces;
    j["seed"] = seed;
    j["triangles"] = scene.triangleCount();
    j["passes_ms"] = passMs;  // summed over the frames, all after every program's warm-up
    // Wall time of each program's first dispatch, one submission each before the frames: its compile
    // where the driver compiles at first dispatch (lavapipe).
    j["program_first_dispatch_ms"] = firstDispatchMs;
    j["traced_spp_last_frame"] = tracedSpp;
    if (method != "reference") {
      j["module_memory_bytes"] = memoryBytes;  // device memory the module holds (FrameStats::memoryBytes)
      j["module_memory_used_bytes"] = memoryUsedBytes;
      j["module_memory_transient_bytes"] = memoryTransientBytes;  // FrameStats::memoryTransientBytes
      j["module_device_allocations"] = deviceAllocations;
      // What gi::predictMemory said before the module existed (held, and its transient part).
      j["module_memory_predicted_bytes"] = predicted.heldBytes;
      j["module_memory_predicted_transient_bytes"] = predicted.transientBytes;
      j["module_memory_bytes_first_frame"] = firstFrameMemoryBytes;
      if (args.has("check-bounds")) j["bounds_violations"] = boundsViolations;
    }
    if (lastHash.capacity)
      j["hash_last_frame"] = {{"capacity", lastHash.capacity},        {"occupied", lastHash.occupied},
                              {"inserts", lastHash.inserts},          {"failed_inserts", lastHash.failedInserts},
                              {"evicted", lastHash.evicted},          {"stale_resets", lastHash.staleResets},
                              {"reads", lastHash.reads},              {"read_misses", lastHash.readMisses},
                              {"transported", lastHash.transported}, {"mean_continuation_depth", lastHash.meanContinuationDepth}};
    j["gpu_ms_total"] = run.gpuMs;
    j["rays"] = run.rays;
    j["mrays_per_second"] = mraysPerSecond;
    j["wall_seconds"] = wall;
    j["validation_messages"] = ctx.validationMessages();
    if (mseVsReference >= 0.0) j["mse_vs_reference"] = mseVsReference;
    std::ofstream f(args.values["stats"]);
    f << j.dump(2) << "\n";
    if (!f) {
      std::fprintf(stderr, "gi-render: %s: cannot write the stats file\n", args.values["stats"].c_str());
      status = 1;
    }
  }
  engine::destroySceneGpu(ctx, sceneGpu);
  uint32_t messages = ctx.validationMessages();
  engine::destroyContext(ctx);
  if (messages > 0) {
    std::fprintf(stderr, "gi-render: %u Vulkan validation message(s); see above\n", messages);
    return 3;
  }
  return status;
}
