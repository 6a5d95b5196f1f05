// gi-bench: measures the speed/accuracy trade. For every configuration
// (method × swept settings × spp) it renders frames through the GI module as a
// game would, times every pass, and compares the result with a converged,
// cached reference. Writes DIR/results.csv, images, and (through
// plot_bench.py) DIR/tradeoff.png, DIR/insets.png and DIR/report.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "bench_configs.h"
#include "camera.h"
#include "cli.h"
#include "metrics.h"
#include "module_session.h"
#include "path_tracer.h"
#include "bench_rays.h"
#include "bench_refit.h"
#include "ray_bench.h"
#include "animation.h"
#include "scene_loading.h"

namespace fs = std::filesystem;

namespace {

const cli::Option kOptions[] = {
    {"scene", "FILE.gltf", "scene to measure (required)"},
    {"size", "WxH", "image size (default 320x180)"},
    {"camera", "N", "glTF camera index (default 0)"},
    {"methods", "A,B,...", "GI module methods to measure (required), e.g. raw"},
    {"spp", "1,2,4,...", "samples per pixel per frame to sweep (default 1)"},
    {"set", "KEY=V1,V2", "settings to sweep; KEY may be prefixed by a method (raw.accumulate=0,1)"},
    {"frames", "N", "timed frames per configuration (default 8); errors are averaged over them"},
    {"warmup", "N", "untimed frames first (default 2)"},
    {"max-bounces", "B", "indirect bounces for methods and reference (default 4)"},
    {"reference", "REF.exr", "use this reference image instead of rendering one"},
    {"reference-spp", "N", "samples per pixel of a rendered reference (default 4096)"},
    {"reference-primary", "traced|gbuffer",
     "rendered references trace from the camera (default), or start from the "
     "raster G-buffer's hits (the module's raw paths accumulated: errors are the "
     "filters' alone, with the G-buffer's seams, near plane and texture mips)"},
    {"camera-path", nullptr,
     "the timed frames walk a scripted camera move (a sideways dolly with a yaw), each compared "
     "with a reference of its own pose: the error columns are the walk's means (per frame: "
     "series.csv), flicker_ratio its frame-to-frame change against the references'"},
    {"path-reference-spp", "N",
     "samples per pixel of each per-frame reference, --camera-path and --animate (default "
     "reference-spp / 4)"},
    {"series", nullptr, "also write series.csv: the error after every timed frame (for temporal methods)"},
    {"animate", nullptr,
     "the light and an object move (engine/animation.h, 30 frames a second); each timed frame is "
     "compared with a reference of its own pose (path-reference-spp)"},
    {"move-at", "F",
     "the light and an object jump half their loop before frame F (warm-up frames count); the reference "
     "shows the moved scene; results get the frames to recover"},
    {"invalidate-at-move", "WHAT",
     "with --move-at: the engine tells the module at the jump, gi::invalidate(all) or "
     "(lights)"},
    {"refit", "N,N,...",
     "only the deforming-mesh microbenchmark: a grid of each triangle count handed over every frame "
     "(gi::updateMeshVertices) against its scene created anew, for each traversal backend; appends "
     "to DIR/refit.csv; then a grid folded step by step, refit against built anew: its BVH level's cost "
     "ratio and Mrays/s, to DIR/refit_quality.csv (no --scene or --methods needed)"},
    {"refit-rebuild", "N,N,...",
     "only the rebuild microbenchmark: a grid of each triangle count folded flat at once, the update that "
     "rebuilds its BVH level against the one that starts it off thread and the one that installs it (CPU ms); "
     "appends to DIR/refit_rebuild.csv (no --scene or --methods needed)"},
    {"rays", nullptr,
     "only the bare-ray microbenchmark: primary, diffuse and shadow Mrays/s for each traversal backend "
     "and for Embree on the CPU; appends to DIR/rays.csv (no --methods needed)"},
    {"history-format", "half|single",
     "the light the temporal passes blend: radiance histories and noisy indirect "
     "(ModuleDesc::historyFormat; default half)"},
    cli::kTraversalOption,
    cli::kSkyOption,
    cli::kPointLightsOption,
    cli::kLightSamplerOption,
    cli::kLightTreeCutOption,
    {"out", "DIR", "output folder (default bench_out)"},
    {"no-plots", nullptr, "skip plot_bench.py (plots and report)"},
    {"validation", nullptr, "enable Vulkan validation"},
    {"help", nullptr, "show this message"},
};
const char* kSynopsis = "--scene FILE.gltf --methods raw,... [options]";

int usageError(const std::string& message) {
  std::fprintf(stderr, "gi-bench: %s\n%s", message.c_str(), cli::usage("gi-bench", kSynopsis, kOptions).c_str());
  return 2;
}

std::string sanitise(const std::string& text) {
  std::string out;
  for (char c : text) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
  return out;
}

// A configuration's last frame, relative to the run's directory (results.csv's `image`, which
// plot_bench.py reads).
std::string imagePath(const std::string& label) { return "images/" + sanitise(label) + ".pfm"; }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Luminance change between consecutive frames, averaged over pixels.
double meanFrameDifference(const engine::FloatImage& a, const engine::FloatImage& b) {
  double sum = 0.0;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x) sum += std::abs(metrics::luminance(a, x, y) - metrics::luminance(b, x, y));
  return sum / std::max(double(a.width) * double(a.height), 1.0);
}

// The scripted move: the camera sways sideways, ±4% of the scene extent, and
// turns ±3° about the vertical, one period every 32 frames (up to 0.8% of the
// extent and 0.6° a frame), so every method sees parallax and disocclusion
// and the camera stays where the scene put it (a straight dolly left
// Conference's room within ten frames).
constexpr const char* kWalkKey = "_sway32";  // in the references' cache keys: change it with the walk
engine::Camera pathCamera(const engine::Camera& start, float sceneExtent, uint32_t k) {
  engine::Camera c = start;
  glm::vec3 right = glm::vec3(start.worldFromView[0]);
  const float phase = std::sin(2.0f * std::numbers::pi_v<float> * float(k) / 32.0f);
  float angle = glm::radians(3.0f) * phase;
  glm::mat4 yaw = glm::mat4(glm::mat3(glm::vec3(std::cos(angle), 0, -std::sin(angle)), glm::vec3(0, 1, 0),
                                      glm::vec3(std::sin(angle), 0, std::cos(angle))));
  c.worldFromView = start.worldFromView * yaw;
  c.worldFromView[3] = start.worldFromView[3] + glm::vec4(right * (0.04f * sceneExtent * phase), 0.0f);
  return c;
}

struct Reference {
  engine::FloatImage final, indirect;
};

// The reference with the G-buffer's primary hits: the module's unfiltered
// paths (raw) from the same raster G-buffer, accumulated at a still camera
// (own seed) to `spp` samples. The filters' errors then mean the filters'
// alone: same first surface (seams and the near plane as the raster sees
// them), same textures at the same mip level.
bool gbufferReference(const engine::Context& ctx, const engine::Scene& scene, const engine::SceneGpu& sceneGpu,
                      const gpu::GpuCamera& camera, uint32_t bounces, uint32_t spp, Reference& out,
                      std::string& error) {
  const VkExtent2D extent{uint32_t(camera.imageSize.x), uint32_t(camera.imageSize.y)};
  gi::Settings settings;
  settings.method = gi::Method::Raw;
  settings.maxBounces = bounces;
  settings.seed = 0x5eed;  // not the measured runs' samples
  settings.raw.samplesPerPixel = std::min(spp, 64u);
  settings.raw.temporalAccumulation = true;
  settings.raw.maxAccumulatedFrames = 1u << 20;
  gi::ModuleDesc desc = tools::moduleDesc(ctx, sceneGpu, extent);
  desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // a converged image needs no half-float rounding
  tools::ModuleSession session;
  if (!tools::createModuleSession(ctx, sceneGpu, extent, settings, session, error, &desc)) return false;
  const uint32_t frames = (spp + settings.raw.samplesPerPixel - 1) / settings.raw.samplesPerPixel;
  for (uint32_t f = 0; f < frames; ++f) tools::renderModuleFrame(ctx, session, scene, sceneGpu, camera, camera, f);
  engine::ReferenceImages images = tools::readModuleImages(ctx, session);
  error = session.error;
  tools::destroyModuleSession(ctx, session);
  out.final = std::move(images.final);
  out.indirect = std::move(images.indirect);
  return error.empty();
}

// The cached reference's name for `key` (from the G-buffer's hits: "_gb" appended), and where its image
// `aov` (final, indirect) lives: the one place both are made (run.txt's reference_final line hands the
// path to scripts/bench).
std::string referenceName(const std::string& key, bool gbufferPrimary) { return gbufferPrimary ? key + "_gb" : key; }
fs::path referencePath(const fs::path& dir, const std::string& key, bool gbufferPrimary, const char* aov) {
  return dir / ("ref_" + referenceName(key, gbufferPrimary) + "_" + aov + ".exr");
}

// Loads the cached reference for `key` or renders and caches it: traced from
// the camera through pixel centres (to match the raster G-buffer), or, with
// `gbufferPrimary`, from the G-buffer's hits (gbufferReference; key + "_gb").
bool reference(const engine::Context& ctx, const engine::Scene& scene, const engine::SceneGpu& sceneGpu,
               const gpu::GpuCamera& camera, uint32_t bounces, uint32_t spp, bool gbufferPrimary, const fs::path& dir,
               const std::string& key, Reference& out, std::string& error) {
  const fs::path finalPath = referencePath(dir, key, gbufferPrimary, "final"),
                 indirectPath = referencePath(dir, key, gbufferPrimary, "indirect");
  if (fs::exists(finalPath) && fs::exists(indirectPath))
    return engine::readImage(finalPath, out.final, error) && engine::readImage(indirectPath, out.indirect, error);
  std::printf("gi-bench: rendering reference %s (%u spp)...\n", referenceName(key, gbufferPrimary).c_str(), spp);
  std::fflush(stdout);
  if (gbufferPrimary) {
    if (!gbufferReference(ctx, scene, sceneGpu, camera, bounces, spp, out, error)) return false;
  } else {
    engine::ReferenceSettings settings;
    settings.maxBounces = bounces;
    settings.pixelJitter = false;
    settings.seed = 0x5eed;
    engine::ReferenceRun run = engine::renderReference(ctx, sceneGpu, camera, settings, spp, 8, error);
    if (!error.empty()) return false;
    out.final = run.images.final;
    out.indirect = run.images.indirect;
  }
  return engine::writeImage(finalPath, out.final, error) && engine::writeImage(indirectPath, out.indirect, error);
}

struct Row {
  tools::BenchConfig config;
  double totalMs = 0.0, traceMs = 0.0;
  std::map<std::string, double> passMs;
  std::vector<std::string> passOrder;
  double rays = 0.0;
  metrics::ImageError final, indirect;
  uint64_t memory = 0;
  double speedup = 0.0;          // equal final-image MSE
  double speedupIndirect = 0.0;  // equal indirect MSE (the papers compare indirect light alone)
  double flickerRatio = -1.0;
  gi::FrameStats::Hash hash;  // telemetry of the last timed frame
  uint32_t tracedSpp = 0;     // paths per pixel the module traced (AAF: its adaptive mean)
  int recoveryFrames = -1;    // --move-at: frames after the move until the indirect error is below 2× its steady state
  double steadyMse = 0.0;     // --move-at: mean indirect error over the last quarter of the frames after the move
};

// --move-at: the steady state is the mean error over the last quarter of the
// frames after the move; recovery is the first of those frames (1 = the frame
// of the move) whose error is below twice that.
void recovery(const std::vector<double>& afterMove, int& frames, double& steady) {
  frames = -1;
  steady = 0.0;
  if (afterMove.size() < 4) return;
  size_t tail = afterMove.size() / 4;
  for (size_t i = afterMove.size() - tail; i < afterMove.size(); ++i) steady += afterMove[i] / double(tail);
  for (size_t i = 0; i < afterMove.size(); ++i)
    if (afterMove[i] < 2.0 * steady) {
      frames = int(i) + 1;
      return;
    }
}

}  // namespace

// --refit and --refit-rebuild: the deforming-mesh microbenchmarks alone (tools/bench_refit.h).
int refitOnly(cli::Args& args) {
  std::vector<uint32_t> counts;
  std::string error;
  const std::string option = args.has("refit") ? "refit" : "refit-rebuild";
  for (const std::string& s : cli::splitList(args.values[option])) {
    cli::Args one;
    one.values[option] = s;
    uint32_t v;
    if (!cli::getUint(one, option, 1000, 2, 1u << 24, v, error)) return usageError(error);
    counts.push_back(v);
  }
  engine::ContextDesc desc;
  desc.validation = args.has("validation");
  if (!cli::getTraversal(args, desc.traversal, error)) return usageError(error);
  const fs::path dir = args.has("out") ? args.values["out"] : "bench_out";
  std::error_code ec;
  fs::create_directories(dir, ec);
  engine::Context ctx;
  if (!engine::createContext(desc, ctx, error)) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    return 1;
  }
  const bool written = option == "refit"
                           ? tools::benchRefit(ctx, counts, dir, error) && tools::benchRefitQuality(ctx, dir, error)
                           : tools::benchRefitRebuild(ctx, counts, dir, error);
  if (!written) std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
  engine::destroyContext(ctx);
  return written ? 0 : 1;
}

namespace {

// What the command line asks for, checked.
struct BenchOptions {
  uint32_t width = 320, height = 180, cameraIndex = 0, frames = 8, warmup = 2, bounces = 4;
  uint32_t refSpp = 4096, pathRefSpp = 1024, moveAt = 0;
  bool animate = false, move = false, cameraPath = false, raysOnly = false, gbufferPrimary = false;
  bool series = false, plots = true;
  std::string scenePath, referenceFile;  // referenceFile: --reference, empty when rendered
  std::string history = "half";
  VkFormat historyFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  std::optional<gi::Invalidate> invalidateAtMove;
  std::vector<tools::BenchConfig> configs;
  engine::ContextDesc context;
  uint32_t lightSampler = 2, lightTreeCut = 4;  // SceneCreateDesc's defaults (gpu::LIGHT_SAMPLER_TREE)
  engine::Sky sky;
  fs::path dir = "bench_out";
};

// The experiment's options and how they combine: false with a sentence in `error`.
bool parseExperiment(cli::Args& args, BenchOptions& o, std::string& error) {
  o.raysOnly = args.has("rays");
  if (!args.has("scene") || (!args.has("methods") && !o.raysOnly)) {
    error = "--scene and --methods are required";
    return false;
  }
  o.scenePath = args.values["scene"];
  if (!cli::getSize(args, "size", 320, 180, o.width, o.height, error) ||
      !cli::getUint(args, "camera", 0, 0, 1u << 20, o.cameraIndex, error) ||
      !cli::getUint(args, "frames", 8, 1, 100000, o.frames, error) ||
      !cli::getUint(args, "warmup", 2, 0, 100000, o.warmup, error) ||
      !cli::getUint(args, "max-bounces", 4, 1, 32, o.bounces, error) ||
      !cli::getUint(args, "reference-spp", 4096, 1, 1u << 24, o.refSpp, error) ||
      !cli::getUint(args, "path-reference-spp", std::max(1u, o.refSpp / 4), 1, 1u << 24, o.pathRefSpp, error) ||
      !cli::getUint(args, "move-at", 0, 0, 1u << 20, o.moveAt, error))
    return false;
  o.animate = args.has("animate");
  o.move = args.has("move-at");
  o.cameraPath = args.has("camera-path");
  if (args.has("reference")) o.referenceFile = args.values["reference"];
  auto refuse = [&](const std::string& why) {
    error = why;
    return false;
  };
  if (o.animate && o.move) return refuse("--animate and --move-at are two different experiments; choose one");
  if (o.animate && !o.referenceFile.empty()) return refuse("--animate renders a reference per frame; drop --reference");
  if (o.cameraPath && (o.animate || o.move))
    return refuse("--camera-path moves the camera, --animate and --move-at the scene; choose one");
  if (o.cameraPath && o.frames < 2) return refuse("--camera-path walks the timed frames: --frames must be 2 or more");
  const std::string primary = args.has("reference-primary") ? args.values["reference-primary"] : "traced";
  if (primary != "traced" && primary != "gbuffer")
    return refuse("--reference-primary: '" + primary + "' is not traced or gbuffer");
  o.gbufferPrimary = primary == "gbuffer";
  if (args.has("history-format")) o.history = args.values["history-format"];
  if (o.history != "half" && o.history != "single")
    return refuse("--history-format: '" + o.history + "' is not half or single");
  o.historyFormat = o.history == "half" ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
  if (args.has("invalidate-at-move")) {
    const std::string& what = args.values["invalidate-at-move"];
    if (!o.move) return refuse("--invalidate-at-move needs --move-at");
    if (what == "all")
      o.invalidateAtMove = gi::Invalidate::All;
    else if (what == "lights")
      o.invalidateAtMove = gi::Invalidate::LightsChanged;
    else
      return refuse("--invalidate-at-move: '" + what + "' is neither all nor lights");
  }
  return true;
}

// The configurations, the device and the scene's lights and sky: false with a sentence in `error`.
bool parseConfigurations(cli::Args& args, BenchOptions& o, std::string& error) {
  std::vector<uint32_t> spps;
  for (const std::string& s : cli::splitList(args.has("spp") ? args.values["spp"] : "1")) {
    cli::Args one;
    one.values["spp"] = s;
    uint32_t v;
    if (!cli::getUint(one, "spp", 1, 1, 64, v, error)) return false;
    spps.push_back(v);
  }
  gi::Settings base;
  base.maxBounces = o.bounces;
  base.seed = 7;
  if (!o.raysOnly &&
      !tools::expandConfigs(cli::splitList(args.values["methods"]), spps, args.values["set"], base, o.configs, error))
    return false;
  o.context.validation = args.has("validation");
  o.series = args.has("series") || o.cameraPath;
  o.plots = !args.has("no-plots");
  if (args.has("out")) o.dir = args.values["out"];
  return cli::getTraversal(args, o.context.traversal, error) &&
         cli::getLightSampler(args, o.lightSampler, o.lightTreeCut, error) && cli::getSky(args, o.sky, error);
}

// What a run holds: the device and the scene on it (released once, by the destructor), the camera, the
// scene's motion, the references and the bare-ray ceiling.
struct Bench {
  engine::Context ctx;
  engine::Scene scene;
  engine::SceneGpu sceneGpu;
  bool sceneOnDevice = false;
  engine::Camera startCamera;
  gpu::GpuCamera camera{};
  engine::SceneAnimation animation;
  float movedSeconds = 0.0f;
  std::string sceneName, key;  // key: the references' cache key
  Reference ref;
  std::vector<Reference> animationRefs, pathRefs;  // --animate, --camera-path: one per timed frame
  double refFlicker = 0.0;  // --camera-path: the references' mean change between consecutive frames
  engine::RayBenchResult bare;

  Bench() = default;
  Bench(const Bench&) = delete;
  Bench& operator=(const Bench&) = delete;
  ~Bench() {
    if (sceneOnDevice) engine::destroySceneGpu(ctx, sceneGpu);
    engine::destroyContext(ctx);
  }
  // The scene at `seconds` of its animation; false with `error` when the module refuses the pose.
  bool pose(float seconds, std::string& error) {
    return engine::poseScene(ctx, animation, seconds, scene, sceneGpu, error);
  }
};

constexpr float kFrameSeconds = 1.0f / 30.0f;

// The output folder, the scene with its lights, the device and the scene on it. False with `error`.
bool openBench(const BenchOptions& o, cli::Args& args, Bench& b, std::string& error) {
  std::error_code ec;
  fs::create_directories(o.dir / "images", ec);
  if (ec) {
    error = o.dir.string() + ": cannot create the output folder (" + ec.message() + ")";
    return false;
  }
  if (!engine::loadSceneForRendering(o.scenePath, b.scene, error) || !cli::applyPointLights(args, b.scene, error))
    return false;
  b.scene.lightSampler = o.lightSampler;
  b.scene.lightTreeCut = o.lightTreeCut;
  if (o.cameraIndex >= b.scene.cameras.size()) {
    error = b.scene.sourcePath + ": camera " + std::to_string(o.cameraIndex) + " does not exist";
    return false;
  }
  if (!engine::createContext(o.context, b.ctx, error)) return false;
  b.scene.sky = o.sky;
  b.scene.bothTraversals = o.raysOnly;  // --rays measures both backends on one scene
  if (!engine::createSceneGpu(b.ctx, b.scene, b.sceneGpu, error)) return false;
  b.sceneOnDevice = true;
  b.startCamera = b.scene.cameras[o.cameraIndex];
  b.camera = engine::makeGpuCamera(b.startCamera, o.width, o.height, nullptr);
  b.sceneName = fs::path(b.scene.sourcePath).stem().string();
  b.key = sanitise(b.sceneName) + "_cam" + std::to_string(o.cameraIndex) + "_" + std::to_string(o.width) + "x" +
          std::to_string(o.height) + "_b" + std::to_string(o.bounces) + "_s" + std::to_string(o.refSpp) +
          cli::skyKey(b.scene.sky) + cli::pointLightsKey(args) + cli::lightSamplerKey(b.scene, b.sceneGpu.desc);
  // Moving scenes: the pose at a time, uploaded (TLAS rebuilt) before the next frame.
  b.animation = engine::makeSceneAnimation(b.scene);
  b.movedSeconds = 0.5f * b.animation.periodSeconds;
  if (o.move) {
    if (!b.pose(b.movedSeconds, error)) return false;
    b.key += "_moved";
  }
  return true;
}

// --camera-path: the camera of timed frame f (warm-up frames stand at the start).
gpu::GpuCamera walkCamera(const BenchOptions& o, const Bench& b, uint32_t f, const gpu::GpuCamera* previous) {
  return engine::makeGpuCamera(pathCamera(b.startCamera, b.sceneGpu.desc.extent, f), o.width, o.height, previous);
}

// --reference: the given image (and, for one gi-bench cached, its indirect AOV beside it), of the run's size.
bool readGivenReference(const BenchOptions& o, Reference& ref, std::string& error) {
  if (!engine::readImage(o.referenceFile, ref.final, error)) return false;
  std::string indirectPath = o.referenceFile;
  const size_t at = indirectPath.rfind("_final.exr");
  if (at != std::string::npos && at + 10 == indirectPath.size()) {
    indirectPath.replace(at, 10, "_indirect.exr");
    std::string ignored;
    if (fs::exists(indirectPath) && !engine::readImage(indirectPath, ref.indirect, ignored))
      ref.indirect = engine::FloatImage();
  }
  if (ref.final.width != o.width || ref.final.height != o.height) {
    error = o.referenceFile + ": the reference is " + std::to_string(ref.final.width) + "x" +
            std::to_string(ref.final.height) + ", not " + std::to_string(o.width) + "x" + std::to_string(o.height);
    return false;
  }
  return true;
}

// The references: the run's (given or cached), one per timed frame's pose with --animate, one per camera of
// the walk with --camera-path (cached like the main one). False with `error`.
bool loadReferences(const BenchOptions& o, Bench& b, std::string& error) {
  const bool loaded = o.referenceFile.empty() ? reference(b.ctx, b.scene, b.sceneGpu, b.camera, o.bounces, o.refSpp,
                                                          o.gbufferPrimary, o.dir, b.key, b.ref, error)
                                              : readGivenReference(o, b.ref, error);
  if (!loaded) return false;
  engine::writeImage((o.dir / "images" / "reference.pfm").string(), b.ref.final, error);
  const std::string perFrameSpp = "_s" + std::to_string(o.pathRefSpp);
  for (uint32_t f = 0; o.animate && f < o.frames; ++f) {
    if (!b.pose(float(o.warmup + f) * kFrameSeconds, error)) return false;
    Reference r;
    if (!reference(b.ctx, b.scene, b.sceneGpu, b.camera, o.bounces, o.pathRefSpp, o.gbufferPrimary, o.dir,
                   b.key + "_anim" + std::to_string(o.warmup + f) + perFrameSpp, r, error))
      return false;
    b.animationRefs.push_back(std::move(r));
  }
  for (uint32_t f = 0; o.cameraPath && f < o.frames; ++f) {
    Reference r;
    if (!reference(b.ctx, b.scene, b.sceneGpu, walkCamera(o, b, f, nullptr), o.bounces, o.pathRefSpp, o.gbufferPrimary,
                   o.dir, b.key + kWalkKey + "_path" + std::to_string(f) + perFrameSpp, r, error))
      return false;
    b.pathRefs.push_back(std::move(r));
    if (f > 0) b.refFlicker += meanFrameDifference(b.pathRefs[f].final, b.pathRefs[f - 1].final) / double(o.frames - 1);
  }
  return true;
}

metrics::ImageError averageError(const std::vector<metrics::ImageError>& v) {
  metrics::ImageError a;
  for (const auto& e : v) {
    a.mse += e.mse / double(v.size());
    a.relMse += e.relMse / double(v.size());
    a.ssim += e.ssim / double(v.size());
  }
  a.psnr = metrics::psnrFromMse(a.mse);
  return a;
}

// One configuration's frames as they run: pass times, rays and errors per timed frame.
struct FrameSamples {
  std::set<std::string> tracingPasses;
  std::map<std::string, std::vector<double>> passMs;
  std::vector<double> totals, rays, afterMove;
  std::vector<metrics::ImageError> finals, indirects;
  uint32_t staleResets = 0;  // over the timed frames (the stats hold one frame's)
  double flicker = 0.0;      // --camera-path: mean change between consecutive frames
  engine::ReferenceImages last;
};

// The scene's pose for a frame: moving with --animate, before and after the jump with --move-at; and the
// engine's word to the module at the jump.
bool poseFrame(const BenchOptions& o, Bench& b, tools::ModuleSession& session, uint32_t frame, std::string& error) {
  if (o.animate && !b.pose(float(frame) * kFrameSeconds, error)) return false;
  if (!o.animate && o.move && (frame == 0 || frame == o.moveAt) &&
      !engine::jumpScene(b.ctx, b.animation, frame < o.moveAt ? 0.0f : b.movedSeconds, b.scene, b.sceneGpu, error))
    return false;
  if (o.invalidateAtMove && o.move && frame == o.moveAt) gi::invalidate(session.module, *o.invalidateAtMove);
  return true;
}

// Timed frame f (frame `frame` of the run): rendered, timed, read back and compared with its reference.
bool measureFrame(const BenchOptions& o, Bench& b, tools::ModuleSession& session, const tools::BenchConfig& config,
                  uint32_t f, uint32_t frame, gpu::GpuCamera& previousCamera, Row& row, FrameSamples& s,
                  std::ofstream& series, std::string& error) {
  if (!poseFrame(o, b, session, frame, error)) return false;
  const Reference& frameRef = o.animate ? b.animationRefs[f] : o.cameraPath ? b.pathRefs[f] : b.ref;
  const gpu::GpuCamera frameCamera = o.cameraPath ? walkCamera(o, b, f, &previousCamera) : b.camera;
  tools::FrameTiming t =
      tools::renderModuleFrame(b.ctx, session, b.scene, b.sceneGpu, frameCamera, previousCamera, frame);
  previousCamera = frameCamera;
  // A pass that runs several times a frame (à-trous iterations, the guided filter's two box
  // passes) counts with its frame total.
  std::map<std::string, double> frameTotals;
  for (const gi::PassTiming& p : t.passes) {
    if (!s.passMs.count(p.name) && !frameTotals.count(p.name)) row.passOrder.push_back(p.name);
    frameTotals[p.name] += p.ms;
    if (p.tracesRays) s.tracingPasses.insert(p.name);  // the module says which passes trace
  }
  for (const auto& [name, ms] : frameTotals) s.passMs[name].push_back(ms);
  s.totals.push_back(t.totalMs);
  s.rays.push_back(double(t.rays));
  const gi::FrameStats frameStats = gi::stats(session.module);
  s.staleResets += frameStats.hash.staleResets;
  engine::FloatImage lastFinal = std::move(s.last.final);
  s.last = tools::readModuleImages(b.ctx, session);
  if (!session.error.empty()) {
    error = config.label + ": " + session.error;
    return false;
  }
  if (o.cameraPath && f > 0) s.flicker += meanFrameDifference(s.last.final, lastFinal) / double(o.frames - 1);
  s.finals.push_back(metrics::compare(s.last.final, frameRef.final));
  if (!frameRef.indirect.pixels.empty()) s.indirects.push_back(metrics::compare(s.last.indirect, frameRef.indirect));
  // The caches hold indirect light: recovery is judged on it (on the final image without an indirect reference).
  if (o.move && frame >= o.moveAt)
    s.afterMove.push_back(s.indirects.empty() ? s.finals.back().mse : s.indirects.back().mse);
  if (series.is_open())
    series << '"' << config.label << "\"," << frame + 1 << ',' << s.finals.back().mse << ',' << s.finals.back().relMse
           << ',' << (s.indirects.empty() ? 0.0 : s.indirects.back().mse) << ','
           << (s.indirects.empty() ? 1.0 : s.indirects.back().energy) << ',' << frameStats.hash.occupancy() << ','
           << frameStats.hash.staleResets << ','
           << (frameStats.hash.reads ? double(frameStats.hash.readMisses) / frameStats.hash.reads : 0.0) << ','
           << frameStats.hash.evicted << "\n";
  return true;
}

// One configuration: a module session, its programs warmed, the warm-up frames, the timed frames, and the
// row of medians and mean errors. False with `error` when the session cannot be made.
// A configuration's session: its programs warmed, the warm-up frames, the timed frames, and the row of
// medians and mean errors. False with `error` when a pose is refused.
bool runConfig(const BenchOptions& o, Bench& b, const tools::BenchConfig& config, tools::ModuleSession& session,
               std::ofstream& series, Row& row, std::string& warmed, std::string& error) {
  // Every program's first dispatch before any frame: no frame, timed or not, times a compiler.
  double warmMs = 0.0;
  for (const tools::ProgramWarmup& w :
       tools::warmModulePrograms(b.ctx, session, config.settings, b.scene, b.sceneGpu, b.camera))
    warmMs += w.ms;
  warmed = config.label + " " + std::to_string(int(warmMs + 0.5)) + " ms";
  uint32_t frame = 0;
  for (; frame < o.warmup; ++frame) {
    if (!poseFrame(o, b, session, frame, error)) return false;
    tools::renderModuleFrame(b.ctx, session, b.scene, b.sceneGpu, b.camera, b.camera, frame);
  }
  FrameSamples s;
  gpu::GpuCamera previousCamera = b.camera;  // the walk starts where the warm-up stood
  for (uint32_t f = 0; f < o.frames; ++f, ++frame)
    if (!measureFrame(o, b, session, config, f, frame, previousCamera, row, s, series, error)) return false;

  for (const auto& [name, samples] : s.passMs) {
    row.passMs[name] = median(samples);
    if (s.tracingPasses.count(name)) row.traceMs += row.passMs[name];
  }
  row.totalMs = median(s.totals);
  for (double r : s.rays) row.rays += r / double(s.rays.size());
  row.final = averageError(s.finals);
  if (!s.indirects.empty()) row.indirect = averageError(s.indirects);
  const gi::FrameStats finalStats = gi::stats(session.module);
  row.memory = finalStats.memoryBytes;
  row.hash = finalStats.hash;
  row.hash.staleResets = s.staleResets;
  row.tracedSpp = finalStats.samplesPerPixel;
  if (o.move) recovery(s.afterMove, row.recoveryFrames, row.steadyMse);
  if ((o.move || o.animate) && !b.pose(0.0f, error)) return false;  // the next configuration starts before the move
  engine::writeImage((o.dir / imagePath(config.label)).string(), s.last.final, error);
  if (o.cameraPath) row.flickerRatio = b.refFlicker > 0.0 ? s.flicker / b.refFlicker : 0.0;
  return true;
}

// One configuration: a module session for it, measured (runConfig), then released. False with `error`.
bool measureConfig(const BenchOptions& o, Bench& b, const tools::BenchConfig& config, std::ofstream& series, Row& row,
                   std::string& warmed, std::string& error) {
  row.config = config;
  tools::ModuleSession session;
  gi::ModuleDesc moduleDesc = tools::moduleDesc(b.ctx, b.sceneGpu, {o.width, o.height});
  moduleDesc.historyFormat = o.historyFormat;
  if (!tools::createModuleSession(b.ctx, b.sceneGpu, {o.width, o.height}, config.settings, session, error,
                                  &moduleDesc)) {
    error = config.label + ": " + error;
    return false;
  }
  const bool measured = runConfig(o, b, config, session, series, row, warmed, error);
  tools::destroyModuleSession(b.ctx, session);
  if (!measured) return false;
  std::printf("gi-bench: %-40s %9.2f ms  MSE %.4e  relMSE %.4e  SSIM %.4f\n", config.label.c_str(), row.totalMs,
              row.final.mse, row.final.relMse, row.final.ssim);
  std::fflush(stdout);
  return true;
}

// Equal-error speed-up against raw MC measured in the same run.
void equalErrorSpeedups(std::vector<Row>& rows) {
  std::vector<double> rawTimes, rawErrors, rawIndirectErrors;
  for (const Row& r : rows)
    if (r.config.settings.method == gi::Method::Raw && !r.config.settings.raw.temporalAccumulation) {
      rawTimes.push_back(r.totalMs);
      rawErrors.push_back(r.final.mse);
      rawIndirectErrors.push_back(r.indirect.mse);
    }
  const double c = metrics::fitInverseLaw(rawTimes, rawErrors);
  const double cIndirect = metrics::fitInverseLaw(rawTimes, rawIndirectErrors);
  for (Row& r : rows) {
    r.speedup = metrics::equalErrorSpeedup(c, r.totalMs, r.final.mse);
    r.speedupIndirect = metrics::equalErrorSpeedup(cIndirect, r.totalMs, r.indirect.mse);
  }
}

std::string format(const char* spec, auto value) {
  char text[256];
  std::snprintf(text, sizeof(text), spec, value);
  return text;
}

// results.csv: each column's name beside its value (plot_bench.py and scripts/bench read the names).
struct RunFacts {
  const std::string& sceneName;
  uint32_t frames;
  double bareMrays;
};
struct Column {
  const char* name;
  std::string (*value)(const Row&, const RunFacts&);
};
double mraysPerSecond(const Row& r) { return r.traceMs > 0.0 ? r.rays / (r.traceMs * 1e3) : 0.0; }
std::string passTimes(const Row& r) {
  std::string passes;
  for (const std::string& name : r.passOrder)
    passes += (passes.empty() ? "" : ";") + name + ":" + format("%.3f", r.passMs.at(name));
  return passes;
}
std::string quoted(const std::string& text) { return '"' + text + '"'; }
const Column kColumns[] = {
    {"scene", [](const Row&, const RunFacts& f) { return f.sceneName; }},
    {"method", [](const Row& r, const RunFacts&) { return std::string(gi::methodName(r.config.settings.method)); }},
    {"settings", [](const Row& r, const RunFacts&) { return quoted(r.config.settingsText); }},
    {"spp", [](const Row& r, const RunFacts&) { return format("%u", r.config.spp); }},
    {"frames", [](const Row&, const RunFacts& f) { return format("%u", f.frames); }},
    {"total_ms", [](const Row& r, const RunFacts&) { return format("%.4f", r.totalMs); }},
    {"pass_ms", [](const Row& r, const RunFacts&) { return passTimes(r); }},
    {"rays", [](const Row& r, const RunFacts&) { return format("%.0f", r.rays); }},
    {"mrays_per_s", [](const Row& r, const RunFacts&) { return format("%.4f", mraysPerSecond(r)); }},
    {"ray_efficiency",
     [](const Row& r, const RunFacts& f) {
       return format("%.4f", f.bareMrays > 0 ? mraysPerSecond(r) / f.bareMrays : 0.0);
     }},
    {"mse", [](const Row& r, const RunFacts&) { return format("%.6e", r.final.mse); }},
    {"relmse", [](const Row& r, const RunFacts&) { return format("%.6e", r.final.relMse); }},
    {"psnr", [](const Row& r, const RunFacts&) { return format("%.4f", r.final.psnr); }},
    {"ssim", [](const Row& r, const RunFacts&) { return format("%.6f", r.final.ssim); }},
    {"mse_indirect", [](const Row& r, const RunFacts&) { return format("%.6e", r.indirect.mse); }},
    {"relmse_indirect", [](const Row& r, const RunFacts&) { return format("%.6e", r.indirect.relMse); }},
    {"psnr_indirect", [](const Row& r, const RunFacts&) { return format("%.4f", r.indirect.psnr); }},
    {"ssim_indirect", [](const Row& r, const RunFacts&) { return format("%.6f", r.indirect.ssim); }},
    {"memory_bytes", [](const Row& r, const RunFacts&) { return format("%llu", (unsigned long long)r.memory); }},
    {"equal_error_speedup", [](const Row& r, const RunFacts&) { return format("%.4f", r.speedup); }},
    {"flicker_ratio",
     [](const Row& r, const RunFacts&) { return r.flickerRatio >= 0.0 ? std::to_string(r.flickerRatio) : ""; }},
    {"hash_occupancy", [](const Row& r, const RunFacts&) { return format("%.4f", double(r.hash.occupancy())); }},
    {"hash_failed_inserts", [](const Row& r, const RunFacts&) { return format("%u", r.hash.failedInserts); }},
    {"hash_mean_probe", [](const Row& r, const RunFacts&) { return format("%.3f", double(r.hash.meanProbe)); }},
    {"hash_max_probe", [](const Row& r, const RunFacts&) { return format("%u", r.hash.maxProbe); }},
    {"hash_evicted", [](const Row& r, const RunFacts&) { return format("%u", r.hash.evicted); }},
    {"traced_spp", [](const Row& r, const RunFacts&) { return format("%u", r.tracedSpp); }},
    {"equal_error_speedup_indirect", [](const Row& r, const RunFacts&) { return format("%.4f", r.speedupIndirect); }},
    {"hash_stale_resets", [](const Row& r, const RunFacts&) { return format("%u", r.hash.staleResets); }},
    {"move_recovery_frames", [](const Row& r, const RunFacts&) { return format("%d", r.recoveryFrames); }},
    {"move_steady_mse_indirect", [](const Row& r, const RunFacts&) { return format("%.6e", r.steadyMse); }},
    {"label", [](const Row& r, const RunFacts&) { return quoted(r.config.label); }},
    {"image", [](const Row& r, const RunFacts&) { return imagePath(r.config.label); }},
};

void writeResults(const fs::path& path, const std::vector<Row>& rows, const RunFacts& facts) {
  std::ofstream csv(path);
  for (const Column& c : kColumns) csv << (&c == kColumns ? "" : ",") << c.name;
  csv << "\n";
  for (const Row& r : rows) {
    for (const Column& c : kColumns) csv << (&c == kColumns ? "" : ",") << c.value(r, facts);
    csv << "\n";
  }
}

// run.txt: what the run measured on, for scripts/bench and the reports.
void writeRunFacts(const BenchOptions& o, const Bench& b, const std::vector<std::string>& programsWarmed) {
  const bool given = !o.referenceFile.empty();
  std::ofstream meta(o.dir / "run.txt");
  meta << "scene " << b.scene.sourcePath << "\ndevice " << b.ctx.properties.deviceName << "\nsize " << o.width << "x"
       << o.height << "\nmax_bounces " << o.bounces << "\nreference " << (given ? o.referenceFile : b.key)
       << "\nreference_final "
       << (given ? fs::absolute(o.referenceFile) : fs::absolute(referencePath(o.dir, b.key, o.gbufferPrimary, "final")))
              .string()
       << "\nreference_spp " << o.refSpp << "\nframes " << o.frames << "\nwarmup " << o.warmup << "\ntraversal "
       << engine::traversalName(b.ctx.traversal) << "\nbare_mrays_per_s " << b.bare.mraysPerSecond()
       << "\nhistory_format " << o.history << "\n";
  // Each configuration's programs were dispatched once, empty, before its first frame (tools::warmModulePrograms):
  // no frame's timing includes a compile. The sums are those first dispatches' wall time.
  for (const std::string& w : programsWarmed) meta << "programs_warmed_before_frames " << w << "\n";
}

// Every configuration measured and written (results.csv, series.csv, run.txt). False with `error` when a
// configuration's session could not be made (the rows measured before it are still written).
bool measureAll(const BenchOptions& o, Bench& b, std::string& error) {
  // The tracing passes' ceiling: the active backend's camera + diffuse rays.
  b.bare = engine::runRayBench(b.ctx, b.sceneGpu, b.camera, gpu::RB_KIND_DIFFUSE, b.ctx.traversalId(), error);
  if (!error.empty()) return false;
  std::printf("gi-bench: bare rays (%s traversal) on %s: %.3f Mrays/s\n", engine::traversalName(b.ctx.traversal),
              b.ctx.properties.deviceName, b.bare.mraysPerSecond());
  std::vector<Row> rows;
  std::ofstream series;
  if (o.series) {
    series.open(o.dir / "series.csv");
    series << "label,frame,mse,relmse,mse_indirect,energy_indirect,hash_occupancy,hash_stale_resets,hash_read_misses,"
              "hash_evicted\n";
  }
  std::vector<std::string> programsWarmed;  // per configuration: its programs' first dispatches, summed
  bool ok = true;
  for (const tools::BenchConfig& config : o.configs) {
    Row row;
    std::string warmed;
    if (!measureConfig(o, b, config, series, row, warmed, error)) {
      ok = false;
      break;
    }
    programsWarmed.push_back(warmed);
    rows.push_back(row);
  }
  equalErrorSpeedups(rows);
  const fs::path csvPath = o.dir / "results.csv";
  writeResults(csvPath, rows, {b.sceneName, o.frames, b.bare.mraysPerSecond()});
  if (series.is_open()) series.close();  // complete on disk before plot_bench.py reads it
  writeRunFacts(o, b, programsWarmed);
  std::printf("gi-bench: wrote %s\n", csvPath.c_str());
  std::fflush(stdout);
  return ok;
}

int fail(const std::string& error) {
  std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
  return 1;
}

// --rays: the bare-ray microbenchmark alone (tools/bench_rays.h).
int raysOnly(const BenchOptions& o, cli::Args& args) {
  Bench b;
  std::string error;
  if (!openBench(o, args, b, error)) return fail(error);
  if (!tools::benchRays(b.ctx, b.scene, b.sceneGpu, b.camera, o.dir, error)) return fail(error);
  return 0;
}

// Measured and written; 0, 1 on an error, 3 when validation reported anything.
int runBench(const BenchOptions& o, cli::Args& args) {
  uint32_t messages = 0;
  {
    Bench b;
    std::string error;
    if (!openBench(o, args, b, error) || !loadReferences(o, b, error)) return fail(error);
    const bool measured = measureAll(o, b, error);
    if (!measured) return fail(error);
    messages = b.ctx.validationMessages();
  }
  if (o.plots) {
    std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string cmd = python + " \"" GI_SOURCE_DIR "/tools/plot_bench.py\" \"" + o.dir.string() + "\"";
    if (std::system(cmd.c_str()) != 0)
      std::fprintf(stderr, "gi-bench: plot_bench.py failed; results.csv is complete\n");
  }
  if (messages > 0) {
    std::fprintf(stderr, "gi-bench: %u Vulkan validation message(s)\n", messages);
    return 3;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  cli::Args args;
  std::string error;
  if (!cli::parse(argc, argv, kOptions, args, error)) return usageError(error);
  if (args.has("help")) {
    std::printf("%s", cli::usage("gi-bench", kSynopsis, kOptions).c_str());
    return 0;
  }
  if (args.has("refit") || args.has("refit-rebuild")) return refitOnly(args);
  BenchOptions o;
  if (!parseExperiment(args, o, error) || !parseConfigurations(args, o, error)) return usageError(error);
  return o.raysOnly ? raysOnly(o, args) : runBench(o, args);
}
