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
    {"dynamic-resolution", "WxH",
     "module methods: the render size alternates between --size and this one every "
     "4 frames (starting at --size), in the same images (gi::resize within "
     "ModuleDesc::maxWidth x maxHeight); the last frame is written at its size"},
    {"camera", "N", "glTF camera index (default 0; a default camera is made when the file has none)"},
    {"method", "NAME", kMethodHelp.c_str()},
    {"set", "KEY=V", "a GI module setting, repeatable (keys: see --help)"},
    {"spp", "N",
     "samples per pixel per frame (default: 64 for the reference, the method's own default for a module method)"},
    {"frames", "N", "frames to accumulate (default 1); total samples = spp × frames"},
    {"max-bounces", "B", "indirect bounces, 0 = direct light only (default 4)"},
    {"seed", "S", "random seed (default 1); the same seed gives the same image"},
    {"aov", "NAME", "final|direct|indirect|albedo|normal|depth (default final)"},
    {"out", "FILE", "output image: .exr or .pfm (linear) or .png (sRGB)"},
    {"stats", "FILE.json", "write device, timings (each program's first dispatch apart), rays and wall time as JSON"},
    {"compare", "REF.exr",
     "the written image's MSE against this one (same size), printed and in --stats as "
     "mse_vs_reference"},
    {"pixel-centres", nullptr,
     "the reference traces through pixel centres, as the module's G-buffer sees them "
     "(default: jittered within each pixel)"},
    {"validation", nullptr, "enable Vulkan validation; any message makes the run fail"},
    {"check-bounds", nullptr,
     "module methods: check every hash-map index and image coordinate the module's "
     "passes use (gi::ModuleDesc::checkBounds); any outside makes the run fail"},
    cli::kTraversalOption,
    cli::kSkyOption,
    cli::kPointLightsOption,
    cli::kLightSamplerOption,
    cli::kLightTreeCutOption,
    {"window", nullptr, "show the frames in a GLFW window (module methods; needs a display)"},
    {"animate", nullptr,
     "the light and an object move, 30 frames a second (engine/animation.h); the reference "
     "renders the last frame's pose"},
    {"help", nullptr, "show this message"},
};
const char* const kAovs[] = {"final", "direct", "indirect", "albedo", "normal", "depth"};
const char* kSynopsis = "--scene FILE.gltf [options]";

int usageError(const std::string& message) {
  std::fprintf(stderr, "gi-render: %s\n%s", message.c_str(), cli::usage("gi-render", kSynopsis, kOptions).c_str());
  return 2;
}

// What the command line asks for.
struct Options {
  std::string scene, method, aov;
  uint32_t width = 0, height = 0, cameraIndex = 0, spp = 0, frames = 0, bounces = 0, seed = 0;
  uint32_t alternateWidth = 0, alternateHeight = 0;  // --dynamic-resolution (0: none)
  engine::Traversal traversal = engine::Traversal::Auto;
  uint32_t lightSampler = 2, lightTreeCut = 4;  // SceneCreateDesc's defaults (gpu::LIGHT_SAMPLER_TREE)
  engine::Sky sky;
  gi::Settings moduleSettings;  // module methods
  bool windowed = false, animate = false;
  bool module() const { return method != "reference"; }
  // --dynamic-resolution: frame f's render size, alternating every 4 frames from --size.
  VkExtent2D renderSize(uint32_t f) const {
    return alternateWidth && (f / 4) % 2 == 1 ? VkExtent2D{alternateWidth, alternateHeight} : VkExtent2D{width, height};
  }
};

// Fills `o` from `args`; false with `error` for a usage error.
bool parseOptions(cli::Args& args, Options& o, std::string& error) {
  if (!args.has("scene")) return error = "--scene is required", false;
  o.scene = args.values["scene"];
  std::vector<const char*> methodChoices = tools::methodNames();
  methodChoices.insert(methodChoices.begin(), "reference");
  if (!cli::getSize(args, "size", 320, 180, o.width, o.height, error) ||
      !cli::getUint(args, "camera", 0, 0, 1u << 20, o.cameraIndex, error) ||
      !cli::getUint(args, "spp", 64, 1, 1u << 20, o.spp, error) ||
      !cli::getUint(args, "frames", 1, 1, 1u << 20, o.frames, error) ||
      !cli::getUint(args, "max-bounces", 4, 0, 1024, o.bounces, error) ||
      !cli::getUint(args, "seed", 1, 0, UINT32_MAX, o.seed, error) ||
      !cli::getChoice(args, "method", "reference", methodChoices, o.method, error) ||
      !cli::getChoice(args, "aov", "final", kAovs, o.aov, error) || !cli::getTraversal(args, o.traversal, error) ||
      !cli::getLightSampler(args, o.lightSampler, o.lightTreeCut, error) || !cli::getSky(args, o.sky, error))
    return false;
  if (uint64_t(o.spp) * o.frames > (1u << 24)) return error = "spp × frames must not exceed 16777216", false;
  o.windowed = args.has("window");
  o.animate = args.has("animate");
  if (o.windowed && !o.module())
    return error = "--window shows module methods (raw, gif, ...), not the reference", false;
  if (args.has("dynamic-resolution")) {
    if (!cli::getSize(args, "dynamic-resolution", 0, 0, o.alternateWidth, o.alternateHeight, error)) return false;
    if (!o.module() || o.windowed) return error = "--dynamic-resolution is for module methods without --window", false;
  }
  if (!o.module()) return true;
  gi::Settings& settings = o.moduleSettings;
  gi::methodFromName(o.method, settings.method);
  settings.maxBounces = o.bounces;
  settings.seed = o.seed;
  if (args.has("spp")) tools::setSamplesPerPixel(settings, o.spp);
  settings.raw.temporalAccumulation = o.frames > 1;  // a static camera: average the frames
  if (args.has("set"))
    for (const std::string& assignment : cli::splitList(args.values["set"]))
      if (!tools::applySetting(settings, assignment, error)) return false;
  if (gi::Error e = gi::validate(settings)) return error = e.message, false;
  o.spp = tools::samplesPerPixel(settings);  // without --spp: the method's default, not the reference's 64
  return true;
}

// What a run measured.
struct Run {
  engine::ReferenceRun run;
  std::map<std::string, double> passMs;           // summed over frames
  std::map<std::string, double> firstDispatchMs;  // each program's first dispatch, before any timed frame
  gi::FrameStats last;                            // module methods: the last frame's numbers
  gi::MemoryPrediction predicted;                 // module methods: gi::predictMemory before the module was created
  uint64_t firstFrameMemoryBytes = 0;  // module methods: held after the first frame (dynamic resolution: constant)
  uint64_t boundsViolations = 0;       // module methods with --check-bounds: summed over the frames
  VkExtent2D lastSize{};               // the last frame's size (--dynamic-resolution)
};

// The scene and its animation on the device.
struct LoadedScene {
  engine::Scene scene;
  engine::SceneGpu gpu;
  engine::SceneAnimation animation;
};

// The module's frames (on the window with --window); 0, or an exit status.
int renderModule(const engine::Context& ctx, LoadedScene& l, const Options& o, const cli::Args& args, Run& out) {
  std::string error;
  gpu::GpuCamera camera = engine::makeGpuCamera(l.scene.cameras[o.cameraIndex], o.width, o.height, nullptr);
  tools::ModuleSession session;
  gi::ModuleDesc desc = tools::moduleDesc(ctx, l.gpu, {o.width, o.height});
  desc.checkBounds = args.has("check-bounds");
  desc.maxWidth = std::max(o.width, o.alternateWidth);  // dynamic resolution: every image at the larger size
  desc.maxHeight = std::max(o.height, o.alternateHeight);
  if (gi::Error e = gi::predictMemory(desc, o.moduleSettings, out.predicted))
    return std::fprintf(stderr, "gi-render: %s\n", e.message.c_str()), 2;
  if (!tools::createModuleSession(ctx, l.gpu, {o.width, o.height}, o.moduleSettings, session, error, &desc))
    return std::fprintf(stderr, "gi-render: %s\n", error.c_str()), 2;
  for (const tools::ProgramWarmup& w :
       tools::warmModulePrograms(ctx, session, o.moduleSettings, l.scene, l.gpu, camera))
    out.firstDispatchMs[w.name] = w.ms;
  engine::Window window;
  if (o.windowed && !engine::createWindow(ctx, o.width, o.height, "gi-render", window, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    tools::destroyModuleSession(ctx, session);
    return 1;
  }
  int status = 0;
  for (uint32_t f = 0; f < o.frames; ++f) {
    if (o.windowed) {
      // Windowed: the same frame script into the window's command buffer, then present.
      uint32_t image = 0;
      if (engine::windowShouldClose(window)) break;
      const engine::WindowFrame begun = engine::beginWindowFrame(ctx, window, image, error);
      if (begun == engine::WindowFrame::Skipped) continue;
      if (o.animate && begun == engine::WindowFrame::Begun) {
        engine::animateScene(l.animation, float(f) / 30.0f, l.scene);
        engine::recordSceneTransformUpdate(ctx, window.cmd, l.scene, l.gpu, error);
      }
      if (error.empty()) tools::recordModuleFrame(ctx, window.cmd, session, l.scene, l.gpu, camera, camera, f);
      if (error.empty() && session.error.empty())
        engine::endWindowFrame(ctx, window, image, gi::outputs(session.module).composite, {o.width, o.height}, error);
      if (!error.empty() || !session.error.empty()) {
        std::fprintf(stderr, "gi-render: %s\n", error.empty() ? session.error.c_str() : error.c_str());
        status = 1;
        break;
      }
      continue;
    }
    if (o.animate && !engine::poseScene(ctx, l.animation, float(f) / 30.0f, l.scene, l.gpu, error)) {
      std::fprintf(stderr, "gi-render: %s\n", error.c_str());
      status = 1;
      break;
    }
    if (const VkExtent2D size = o.renderSize(f);
        size.width != session.extent.width || size.height != session.extent.height) {
      if (!tools::resizeModuleSession(ctx, session, size, error)) {
        std::fprintf(stderr, "gi-render: %s\n", error.c_str());
        status = 1;
        break;
      }
      camera = engine::makeGpuCamera(l.scene.cameras[o.cameraIndex], size.width, size.height, nullptr);
    }
    tools::FrameTiming t = tools::renderModuleFrame(ctx, session, l.scene, l.gpu, camera, camera, f);
    if (f == 0) out.firstFrameMemoryBytes = gi::stats(session.module).memoryBytes;
    out.boundsViolations += gi::stats(session.module).boundsViolations;
    for (const gi::PassTiming& p : t.passes) out.passMs[p.name] += p.ms;
    out.run.gpuMs += t.totalMs;
    out.run.rays += t.rays;
  }
  if (o.windowed) engine::destroyWindow(ctx, window);
  out.run.images = tools::readModuleImages(ctx, session);
  if (!session.error.empty() && status == 0) {
    std::fprintf(stderr, "gi-render: %s\n", session.error.c_str());
    status = 1;
  }
  out.lastSize = session.extent;
  out.last = gi::stats(session.module);
  tools::destroyModuleSession(ctx, session);
  if (out.boundsViolations > 0) {
    std::fprintf(stderr, "gi-render: %llu accesses outside a buffer or image (--check-bounds)\n",
                 static_cast<unsigned long long>(out.boundsViolations));
    status = 1;
  }
  return status;
}

// The reference path tracer: spp × frames samples of the last frame's pose. 0, or 1 when the pose is refused.
int renderReferenceImage(const engine::Context& ctx, LoadedScene& l, const Options& o, const cli::Args& args,
                         Run& out) {
  engine::ReferenceSettings settings;
  settings.maxBounces = o.bounces;
  settings.seed = o.seed;
  settings.pixelJitter = !args.has("pixel-centres");
  std::string error;
  if (o.animate && !engine::poseScene(ctx, l.animation, float(o.frames - 1) / 30.0f, l.scene, l.gpu, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  const gpu::GpuCamera camera = engine::makeGpuCamera(l.scene.cameras[o.cameraIndex], o.width, o.height, nullptr);
  out.run = engine::renderReference(ctx, l.gpu, camera, settings, o.spp * o.frames, 4, error);
  if (!error.empty()) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  out.lastSize = {o.width, o.height};
  out.passMs["path_trace"] = out.run.gpuMs;
  out.firstDispatchMs["path_trace"] = out.run.firstDispatchMs;
  return 0;
}

// --out: the AOV written; --compare: its MSE against a reference (−1 without). False on a failure, printed.
bool writeImageAndCompare(cli::Args& args, const Options& o, const Run& r, double& mseVsReference) {
  std::string error;
  const engine::ReferenceImages& im = r.run.images;
  const engine::FloatImage& img = o.aov == "direct"     ? im.direct
                                  : o.aov == "indirect" ? im.indirect
                                  : o.aov == "albedo"   ? im.albedo
                                  : o.aov == "normal"   ? im.normal
                                  : o.aov == "depth"    ? im.depth
                                                        : im.final;
  bool ok = true;
  if (args.has("out") && !engine::writeImage(args.values["out"], img, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    ok = false;
  }
  mseVsReference = -1.0;
  if (!args.has("compare")) return ok;
  engine::FloatImage reference;
  if (!engine::readImage(args.values["compare"], reference, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return false;
  }
  if (reference.width != img.width || reference.height != img.height || reference.channels != img.channels) {
    std::fprintf(stderr, "gi-render: %s is %ux%u, the image %ux%u\n", args.values["compare"].c_str(), reference.width,
                 reference.height, img.width, img.height);
    return false;
  }
  mseVsReference = metrics::mse(img, reference);
  std::printf("MSE against %s: %.4e\n", args.values["compare"].c_str(), mseVsReference);
  return ok;
}

// --stats: the run as JSON. False when the file cannot be written.
bool writeStats(const std::string& path, const engine::Context& ctx, const LoadedScene& l, const Options& o,
                const Run& r, double mraysPerSecond, double wallSeconds, double mseVsReference, bool checkBounds) {
  nlohmann::json j;
  j["device"] = ctx.properties.deviceName;
  j["traversal"] = engine::traversalName(ctx.traversal);
  j["scene"] = l.scene.sourcePath;
  j["method"] = o.method;
  j["width"] = r.lastSize.width;
  j["height"] = r.lastSize.height;
  j["spp"] = o.spp * o.frames;
  j["frames"] = o.frames;
  j["max_bounces"] = o.bounces;
  j["seed"] = o.seed;
  j["triangles"] = l.scene.triangleCount();
  // Deformable meshes (gi::SceneInfo): the last measured level's cost over its cost as built, and the
  // rebuilds SceneCreateDesc::rebuildCostRatio made (0 and 0 without deformable meshes).
  const gi::SceneInfo sceneInfo = gi::sceneInfo(l.gpu.scene);
  j["scene_refit_cost_ratio"] = sceneInfo.refitCostRatio;
  j["scene_level_rebuilds"] = sceneInfo.levelRebuilds;
  j["passes_ms"] = r.passMs;  // summed over the frames, all after every program's warm-up
  // Wall time of each program's first dispatch, one submission each before the frames: its compile
  // where the driver compiles at first dispatch (lavapipe).
  j["program_first_dispatch_ms"] = r.firstDispatchMs;
  j["traced_spp_last_frame"] = o.module() ? r.last.samplesPerPixel : o.spp;  // AAF: its adaptive mean
  if (o.module()) {
    j["module_memory_bytes"] = r.last.memoryBytes;  // device memory the module holds (FrameStats::memoryBytes)
    j["module_memory_used_bytes"] = r.last.memoryUsedBytes;
    j["module_memory_transient_bytes"] = r.last.memoryTransientBytes;  // FrameStats::memoryTransientBytes
    j["module_device_allocations"] = r.last.deviceAllocations;
    // What gi::predictMemory said before the module existed (held, and its transient part).
    j["module_memory_predicted_bytes"] = r.predicted.heldBytes;
    j["module_memory_predicted_transient_bytes"] = r.predicted.transientBytes;
    j["module_memory_bytes_first_frame"] = r.firstFrameMemoryBytes;
    if (checkBounds) j["bounds_violations"] = r.boundsViolations;
  }
  const gi::FrameStats::Hash& h = r.last.hash;
  if (h.capacity)
    j["hash_last_frame"] = {{"capacity", h.capacity},
                            {"secondary_width", h.secondaryWidth},
                            {"occupied", h.occupied},
                            {"inserts", h.inserts},
                            {"failed_inserts", h.failedInserts},
                            {"claimed", h.claimed},
                            {"evicted", h.evicted},
                            {"stale_resets", h.staleResets},
                            {"reads", h.reads},
                            {"read_misses", h.readMisses},
                            {"transported", h.transported},
                            {"mean_continuation_depth", h.meanContinuationDepth}};
  j["gpu_ms_total"] = r.run.gpuMs;
  j["rays"] = r.run.rays;
  j["mrays_per_second"] = mraysPerSecond;
  j["wall_seconds"] = wallSeconds;
  j["validation_messages"] = ctx.validationMessages();
  if (mseVsReference >= 0.0) j["mse_vs_reference"] = mseVsReference;
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  if (!f) std::fprintf(stderr, "gi-render: %s: cannot write the stats file\n", path.c_str());
  return bool(f);
}

// The scene as --scene, --point-lights, the light sampler and --sky say; false with `error`.
bool loadScene(cli::Args& args, Options& o, LoadedScene& l, std::string& error) {
  if (!engine::loadSceneForRendering(o.scene, l.scene, error) || !cli::applyPointLights(args, l.scene, error))
    return false;
  l.scene.lightSampler = o.lightSampler;
  l.scene.lightTreeCut = o.lightTreeCut;
  if (o.cameraIndex >= l.scene.cameras.size()) {
    error = l.scene.sourcePath + ": camera " + std::to_string(o.cameraIndex) + " does not exist (the scene has " +
            std::to_string(l.scene.cameras.size()) + ")";
    return false;
  }
  l.scene.sky = std::move(o.sky);
  return true;
}

// The context for the options (a swapchain-capable one with --window); false with `error`.
bool createRenderContext(cli::Args& args, const Options& o, engine::Context& ctx, std::string& error) {
  engine::ContextDesc desc;
  desc.validation = args.has("validation") || std::getenv("GI_VALIDATION") != nullptr;
  desc.traversal = o.traversal;
  if (o.windowed) {
    if (!engine::windowInstanceExtensions(desc.instanceExtensions, error)) return false;
    desc.swapchain = true;
  }
  return engine::createContext(desc, ctx, error);
}

}  // namespace

int main(int argc, char** argv) {
  const auto wallStart = std::chrono::steady_clock::now();
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
  Options o;
  if (!parseOptions(args, o, error)) return usageError(error);
  LoadedScene l;
  engine::Context ctx;
  if (!loadScene(args, o, l, error) || !createRenderContext(args, o, ctx, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    return 1;
  }
  // --animate: the scene's pose for frame f, uploaded before the frame is recorded.
  l.animation = engine::makeSceneAnimation(l.scene);
  if (o.animate) engine::markAnimatedInstancesMovable(l.animation, l.scene);
  if (!engine::createSceneGpu(ctx, l.scene, l.gpu, error)) {
    std::fprintf(stderr, "gi-render: %s\n", error.c_str());
    engine::destroyContext(ctx);
    return 1;
  }

  Run r;
  int status = o.module() ? renderModule(ctx, l, o, args, r) : renderReferenceImage(ctx, l, o, args, r);
  if (r.lastSize.width) {  // frames ran (not: no module, or no window)
    double mseVsReference = -1.0;
    if (!writeImageAndCompare(args, o, r, mseVsReference)) status = 1;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    const double mraysPerSecond = r.run.gpuMs > 0.0 ? double(r.run.rays) / (r.run.gpuMs * 1e3) : 0.0;
    std::printf("%s: %ux%u, %u spp, B=%u on %s (%s traversal): %.1f ms GPU, %llu rays (%.3f Mrays/s), %.2f s wall\n",
                l.scene.sourcePath.c_str(), r.lastSize.width, r.lastSize.height, o.spp * o.frames, o.bounces,
                ctx.properties.deviceName, engine::traversalName(ctx.traversal), r.run.gpuMs,
                (unsigned long long)r.run.rays, mraysPerSecond, wall);
    if (args.has("stats") &&
        !writeStats(args.values["stats"], ctx, l, o, r, mraysPerSecond, wall, mseVsReference, args.has("check-bounds")))
      status = 1;
  }
  engine::destroySceneGpu(ctx, l.gpu);
  const uint32_t messages = ctx.validationMessages();
  engine::destroyContext(ctx);
  if (messages > 0) {
    std::fprintf(stderr, "gi-render: %u Vulkan validation message(s); see above\n", messages);
    return 3;
  }
  return status;
}
