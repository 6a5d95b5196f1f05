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
    {"reference-primary", "traced|gbuffer", "rendered references trace from the camera (default), or start from the "
                                            "raster G-buffer's hits (the module's raw paths accumulated: errors are the "
                                            "filters' alone, with the G-buffer's seams, near plane and texture mips)"},
    {"camera-path", nullptr, "the timed frames walk a scripted camera move (a sideways dolly with a yaw), each compared "
                             "with a reference of its own pose: the error columns are the walk's means (per frame: "
                             "series.csv), flicker_ratio its frame-to-frame change against the references'"},
    {"path-reference-spp", "N", "samples per pixel of each per-frame reference, --camera-path and --animate (default "
                                "reference-spp / 4)"},
    {"series", nullptr, "also write series.csv: the error after every timed frame (for temporal methods)"},
    {"animate", nullptr, "the light and an object move (engine/animation.h, 30 frames a second); each timed frame is "
                         "compared with a reference of its own pose (path-reference-spp)"},
    {"move-at", "F", "the light and an object jump half their loop before frame F (warm-up frames count); the reference "
                     "shows the moved scene; results get the frames to recover"},
    {"invalidate-at-move", "WHAT", "with --move-at: the engine tells the module at the jump, gi::invalidate(all) or "
                                   "(lights)"},
    {"refit", "N,N,...", "only the deforming-mesh microbenchmark: a grid of each triangle count handed over every frame "
                         "(gi::updateMeshVertices) against its scene created anew, for each traversal backend; appends "
                         "to DIR/refit.csv (no --scene or --methods needed)"},
    {"rays", nullptr, "only the bare-ray microbenchmark: primary, diffuse and shadow Mrays/s for each traversal backend "
                      "and for Embree on the CPU; appends to DIR/rays.csv (no --methods needed)"},
    {"history-format", "half|single", "the light the temporal passes blend: radiance histories and noisy indirect "
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
  const float phase = std::sin(2.0f * 3.14159265f * float(k) / 32.0f);
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
                      const gpu::GpuCamera& camera, uint32_t bounces, uint32_t spp, Reference& out, std::string& error) {
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
  tools::destroyModuleSession(ctx, session);
  out.final = std::move(images.final);
  out.indirect = std::move(images.indirect);
  return true;
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
    engine::ReferenceRun run = engine::renderReference(ctx, sceneGpu, camera, settings, spp, 8);
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
  uint32_t tracedSpp = 0;      // paths per pixel the module traced (AAF: its adaptive mean)
  int recoveryFrames = -1;     // --move-at: frames after the move until the indirect error is below 2× its steady state
  double steadyMse = 0.0;      // --move-at: mean indirect error over the last quarter of the frames after the move
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

// --refit: the deforming-mesh microbenchmark alone (tools/bench_refit.h).
int refitOnly(cli::Args& args) {
  std::vector<uint32_t> counts;
  std::string error;
  for (const std::string& s : cli::splitList(args.values["refit"])) {
    cli::Args one;
    one.values["refit"] = s;
    uint32_t v;
    if (!cli::getUint(one, "refit", 1000, 2, 1u << 24, v, error)) return usageError(error);
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
  bool written = false;
  try {
    written = tools::benchRefit(ctx, counts, dir, error);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!written) std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
  engine::destroyContext(ctx);
  return written ? 0 : 1;
}

int main(int argc, char** argv) {
  cli::Args args;
  std::string error;
  if (!cli::parse(argc, argv, kOptions, args, error)) return usageError(error);
  if (args.has("help")) {
    std::printf("%s", cli::usage("gi-bench", kSynopsis, kOptions).c_str());
    return 0;
  }
  if (args.has("refit")) return refitOnly(args);
  const bool raysOnly = args.has("rays");
  if (!args.has("scene") || (!args.has("methods") && !raysOnly)) return usageError("--scene and --methods are required");
  uint32_t width, height, cameraIndex, frames, warmup, bounces, refSpp, pathRefSpp, moveAt = 0;
  if (!cli::getSize(args, "size", 320, 180, width, height, error) ||
      !cli::getUint(args, "camera", 0, 0, 1u << 20, cameraIndex, error) ||
      !cli::getUint(args, "frames", 8, 1, 100000, frames, error) ||
      !cli::getUint(args, "warmup", 2, 0, 100000, warmup, error) ||
      !cli::getUint(args, "max-bounces", 4, 1, 32, bounces, error) ||
      !cli::getUint(args, "reference-spp", 4096, 1, 1u << 24, refSpp, error) ||
      !cli::getUint(args, "path-reference-spp", std::max(1u, refSpp / 4), 1, 1u << 24, pathRefSpp, error) ||
      !cli::getUint(args, "move-at", 0, 0, 1u << 20, moveAt, error))
    return usageError(error);
  const bool animate = args.has("animate"), move = args.has("move-at");
  if (animate && move) return usageError("--animate and --move-at are two different experiments; choose one");
  if (animate && args.has("reference")) return usageError("--animate renders a reference per frame; drop --reference");
  if (args.has("camera-path") && (animate || move))
    return usageError("--camera-path moves the camera, --animate and --move-at the scene; choose one");
  if (args.has("camera-path") && frames < 2) return usageError("--camera-path walks the timed frames: --frames must be 2 or more");
  const std::string primary = args.has("reference-primary") ? args.values["reference-primary"] : "traced";
  if (primary != "traced" && primary != "gbuffer")
    return usageError("--reference-primary: '" + primary + "' is not traced or gbuffer");
  const bool gbufferPrimary = primary == "gbuffer";
  const std::string history = args.has("history-format") ? args.values["history-format"] : "half";
  if (history != "half" && history != "single")
    return usageError("--history-format: '" + history + "' is not half or single");
  const VkFormat historyFormat = history == "half" ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
  std::optional<gi::Invalidate> invalidateAtMove;
  if (args.has("invalidate-at-move")) {
    const std::string& what = args.values["invalidate-at-move"];
    if (!move) return usageError("--invalidate-at-move needs --move-at");
    if (what == "all") invalidateAtMove = gi::Invalidate::All;
    else if (what == "lights") invalidateAtMove = gi::Invalidate::LightsChanged;
    else return usageError("--invalidate-at-move: '" + what + "' is neither all nor lights");
  }
  std::vector<uint32_t> spps;
  for (const std::string& s : cli::splitList(args.has("spp") ? args.values["spp"] : "1")) {
    cli::Args one;
    one.values["spp"] = s;
    uint32_t v;
    if (!cli::getUint(one, "spp", 1, 1, 64, v, error)) return usageError(error);
    spps.push_back(v);
  }
  gi::Settings base;
  base.maxBounces = bounces;
  base.seed = 7;
  std::vector<tools::BenchConfig> configs;
  if (!raysOnly &&
      !tools::expandConfigs(cli::splitList(args.values["methods"]), spps, args.values["set"], base, configs, error))
    return usageError(error);
  engine::ContextDesc desc;
  desc.validation = args.has("validation");
  if (!cli::getTraversal(args, desc.traversal, error)) return usageError(error);
  uint32_t lightSampler = 2, lightTreeCut = 4;  // SceneCreateDesc's defaults (gpu::LIGHT_SAMPLER_TREE)
  if (!cli::getLightSampler(args, lightSampler, lightTreeCut, error)) return usageError(error);
  engine::Sky sky;
  if (!cli::getSky(args, sky, error)) return usageError(error);

  fs::path dir = args.has("out") ? args.values["out"] : "bench_out";
  std::error_code ec;
  fs::create_directories(dir / "images", ec);
  if (ec) {
    std::fprintf(stderr, "gi-bench: %s: cannot create the output folder (%s)\n", dir.c_str(), ec.message().c_str());
    return 1;
  }
  engine::Scene scene;
  if (!engine::loadSceneForRendering(args.values["scene"], scene, error)) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    return 1;
  }
  if (!cli::applyPointLights(args, scene, error)) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    return 1;
  }
  scene.lightSampler = lightSampler;
  scene.lightTreeCut = lightTreeCut;
  if (cameraIndex >= scene.cameras.size()) {
    std::fprintf(stderr, "gi-bench: %s: camera %u does not exist\n", scene.sourcePath.c_str(), cameraIndex);
    return 1;
  }
  engine::Context ctx;
  if (!engine::createContext(desc, ctx, error)) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    return 1;
  }
  engine::SceneGpu sceneGpu;
  scene.sky = std::move(sky);
  scene.bothTraversals = raysOnly;  // --rays measures both backends on one scene
  engine::createSceneGpu(ctx, scene, sceneGpu);
  const engine::Camera& startCamera = scene.cameras[cameraIndex];
  gpu::GpuCamera camera = engine::makeGpuCamera(startCamera, width, height, nullptr);
  if (raysOnly) {
    bool written = tools::benchRays(ctx, scene, sceneGpu, camera, dir, error);
    if (!written) std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    engine::destroySceneGpu(ctx, sceneGpu);
    engine::destroyContext(ctx);
    return written ? 0 : 1;
  }
  std::string sceneName = fs::path(scene.sourcePath).stem().string();
  std::string key = sanitise(sceneName) + "_cam" + std::to_string(cameraIndex) + "_" + std::to_string(width) + "x" +
                    std::to_string(height) + "_b" + std::to_string(bounces) + "_s" + std::to_string(refSpp) +
                    cli::skyKey(scene.sky) + cli::pointLightsKey(args) + cli::lightSamplerKey(scene, sceneGpu.desc);
  // Moving scenes: the pose at a time, uploaded (TLAS rebuilt) before the next frame.
  engine::SceneAnimation animation = engine::makeSceneAnimation(scene);
  auto pose = [&](float seconds) { engine::poseScene(ctx, animation, seconds, scene, sceneGpu); };
  const float movedSeconds = 0.5f * animation.periodSeconds, frameSeconds = 1.0f / 30.0f;
  if (move) {
    pose(movedSeconds);
    key += "_moved";
  }

  Reference ref;
  bool ok = true;
  if (args.has("reference")) {
    ok = engine::readImage(args.values["reference"], ref.final, error);
    // A reference cached by gi-bench (…_final.exr) has its indirect AOV beside it.
    std::string indirectPath = args.values["reference"];
    size_t at = indirectPath.rfind("_final.exr");
    if (ok && at != std::string::npos && at + 10 == indirectPath.size()) {
      indirectPath.replace(at, 10, "_indirect.exr");
      std::string ignored;
      if (fs::exists(indirectPath) && !engine::readImage(indirectPath, ref.indirect, ignored)) ref.indirect = engine::FloatImage();
    }
    if (ok && (ref.final.width != width || ref.final.height != height)) {
      error = args.values["reference"] + ": the reference is " + std::to_string(ref.final.width) + "x" +
              std::to_string(ref.final.height) + ", not " + std::to_string(width) + "x" + std::to_string(height);
      ok = false;
    }
  } else {
    ok = reference(ctx, scene, sceneGpu, camera, bounces, refSpp, gbufferPrimary, dir, key, ref, error);
  }
  if (!ok) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    engine::destroySceneGpu(ctx, sceneGpu);
    engine::destroyContext(ctx);
    return 1;
  }
  engine::writeImage((dir / "images" / "reference.pfm").string(), ref.final, error);
  // --animate: a reference per timed frame, at that frame's pose (cached like the main one).
  std::vector<Reference> animationRefs;
  for (uint32_t f = 0; animate && f < frames && ok; ++f) {
    pose(float(warmup + f) * frameSeconds);
    Reference r;
    ok = reference(ctx, scene, sceneGpu, camera, bounces, pathRefSpp, gbufferPrimary, dir,
                   key + "_anim" + std::to_string(warmup + f) + "_s" + std::to_string(pathRefSpp), r, error);
    animationRefs.push_back(r);
  }
  if (!ok) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    engine::destroySceneGpu(ctx, sceneGpu);
    engine::destroyContext(ctx);
    return 1;
  }

  // --camera-path: the camera of each timed frame (warm-up frames stand at the
  // start) and a reference per pose, cached like the main one.
  const bool cameraPath = args.has("camera-path");
  auto walkCamera = [&](uint32_t f, const gpu::GpuCamera* previous) {
    return engine::makeGpuCamera(pathCamera(startCamera, sceneGpu.desc.extent, f), width, height, previous);
  };
  std::vector<Reference> pathRefs;
  double refFlicker = 0.0;
  for (uint32_t f = 0; cameraPath && f < frames && ok; ++f) {
    Reference r;
    ok = reference(ctx, scene, sceneGpu, walkCamera(f, nullptr), bounces, pathRefSpp, gbufferPrimary, dir,
                   key + kWalkKey + "_path" + std::to_string(f) + "_s" + std::to_string(pathRefSpp), r, error);
    pathRefs.push_back(r);
    if (f > 0) refFlicker += meanFrameDifference(pathRefs[f].final, pathRefs[f - 1].final) / double(frames - 1);
  }
  if (!ok) {
    std::fprintf(stderr, "gi-bench: %s\n", error.c_str());
    engine::destroySceneGpu(ctx, sceneGpu);
    engine::destroyContext(ctx);
    return 1;
  }

  // The tracing passes' ceiling: the active backend's camera + diffuse rays.
  engine::RayBenchResult bare =
      engine::runRayBench(ctx, sceneGpu, camera, gpu::RB_KIND_DIFFUSE, ctx.traversalId());
  std::printf("gi-bench: bare rays (%s traversal) on %s: %.3f Mrays/s\n", engine::traversalName(ctx.traversal),
              ctx.properties.deviceName, bare.mraysPerSecond());

  std::vector<Row> rows;
  std::ofstream series;
  if (args.has("series") || cameraPath) {
    series.open(dir / "series.csv");
    series << "label,frame,mse,relmse,mse_indirect,energy_indirect,hash_occupancy,hash_stale_resets,hash_read_misses,hash_evicted\n";
  }
  std::vector<std::string> programsWarmed;  // per configuration: its programs' first dispatches, summed
  for (const tools::BenchConfig& config : configs) {
    Row row;
    row.config = config;
    tools::ModuleSession session;
    gi::ModuleDesc moduleDesc = tools::moduleDesc(ctx, sceneGpu, {width, height});
    moduleDesc.historyFormat = historyFormat;
    if (!tools::createModuleSession(ctx, sceneGpu, {width, height}, config.settings, session, error, &moduleDesc)) {
      std::fprintf(stderr, "gi-bench: %s: %s\n", config.label.c_str(), error.c_str());
      ok = false;
      break;
    }
    // Every program's first dispatch before any frame: no frame, timed or not, times a compiler.
    double warmMs = 0.0;
    for (const tools::ProgramWarmup& w : tools::warmModulePrograms(ctx, session, config.settings, scene, sceneGpu, camera))
      warmMs += w.ms;
    programsWarmed.push_back(config.label + " " + std::to_string(int(warmMs + 0.5)) + " ms");
    std::set<std::string> tracingPasses;
    std::map<std::string, std::vector<double>> passSamples;
    std::vector<double> totals, rays;
    std::vector<metrics::ImageError> finals, indirects;
    uint32_t frame = 0;
    // The scene's pose for a frame: moving with --animate, before and after the jump with --move-at.
    auto poseFor = [&](uint32_t f) {
      if (animate) pose(float(f) * frameSeconds);
      else if (move && (f == 0 || f == moveAt))
        engine::jumpScene(ctx, animation, f < moveAt ? 0.0f : movedSeconds, scene, sceneGpu);
    };
    std::vector<double> afterMove;
    uint32_t staleResets = 0;  // over the timed frames (the stats hold one frame's)
    for (; frame < warmup; ++frame) {
      poseFor(frame);
      if (invalidateAtMove && move && frame == moveAt) gi::invalidate(session.module, *invalidateAtMove);
      tools::renderModuleFrame(ctx, session, scene, sceneGpu, camera, camera, frame);
    }
    engine::ReferenceImages out;
    gpu::GpuCamera previousCamera = camera;  // the walk starts where the warm-up stood
    double flicker = 0.0;                    // --camera-path: mean change between consecutive frames
    for (uint32_t f = 0; f < frames; ++f, ++frame) {
      poseFor(frame);
      if (invalidateAtMove && move && frame == moveAt) gi::invalidate(session.module, *invalidateAtMove);
      const Reference& frameRef = animate ? animationRefs[f] : cameraPath ? pathRefs[f] : ref;
      const gpu::GpuCamera frameCamera = cameraPath ? walkCamera(f, &previousCamera) : camera;
      tools::FrameTiming t = tools::renderModuleFrame(ctx, session, scene, sceneGpu, frameCamera, previousCamera, frame);
      previousCamera = frameCamera;
      // A pass that runs several times a frame (à-trous iterations, the guided filter's two box
      // passes) counts with its frame total.
      std::map<std::string, double> frameTotals;
      for (const gi::PassTiming& p : t.passes) {
        if (!passSamples.count(p.name) && !frameTotals.count(p.name)) row.passOrder.push_back(p.name);
        frameTotals[p.name] += p.ms;
        if (p.tracesRays) tracingPasses.insert(p.name);  // the module says which passes trace
      }
      for (const auto& [name, ms] : frameTotals) passSamples[name].push_back(ms);
      totals.push_back(t.totalMs);
      rays.push_back(double(t.rays));
      const gi::FrameStats frameStats = gi::stats(session.module);
      staleResets += frameStats.hash.staleResets;
      engine::FloatImage lastFinal = std::move(out.final);
      out = tools::readModuleImages(ctx, session);
      if (cameraPath && f > 0) flicker += meanFrameDifference(out.final, lastFinal) / double(frames - 1);
      finals.push_back(metrics::compare(out.final, frameRef.final));
      if (!frameRef.indirect.pixels.empty()) indirects.push_back(metrics::compare(out.indirect, frameRef.indirect));
      // The caches hold indirect light: recovery is judged on it (on the final image without an indirect reference).
      if (move && frame >= moveAt) afterMove.push_back(indirects.empty() ? finals.back().mse : indirects.back().mse);
      if (series.is_open())
        series << '"' << config.label << "\"," << frame + 1 << ',' << finals.back().mse << ',' << finals.back().relMse << ','
               << (indirects.empty() ? 0.0 : indirects.back().mse) << ',' << (indirects.empty() ? 1.0 : indirects.back().energy)
               << ',' << frameStats.hash.occupancy() << ',' << frameStats.hash.staleResets << ','
               << (frameStats.hash.reads ? double(frameStats.hash.readMisses) / frameStats.hash.reads : 0.0) << ','
               << frameStats.hash.evicted << "\n";
    }
    for (const auto& [name, samples] : passSamples) {
      row.passMs[name] = median(samples);
      if (tracingPasses.count(name)) row.traceMs += row.passMs[name];
    }
    row.totalMs = median(totals);
    for (double r : rays) row.rays += r / double(rays.size());
    auto average = [](const std::vector<metrics::ImageError>& v) {
      metrics::ImageError a;
      for (const auto& e : v) {
        a.mse += e.mse / double(v.size());
        a.relMse += e.relMse / double(v.size());
        a.ssim += e.ssim / double(v.size());
      }
      a.psnr = metrics::psnrFromMse(a.mse);
      return a;
    };
    row.final = average(finals);
    if (!indirects.empty()) row.indirect = average(indirects);
    gi::FrameStats finalStats = gi::stats(session.module);
    row.memory = finalStats.memoryBytes;
    row.hash = finalStats.hash;
    row.hash.staleResets = staleResets;
    row.tracedSpp = finalStats.samplesPerPixel;
    if (move) {
      recovery(afterMove, row.recoveryFrames, row.steadyMse);
      pose(0.0f);  // the next configuration starts before the move
    }
    if (animate) pose(0.0f);
    engine::writeImage((dir / imagePath(config.label)).string(), out.final, error);

    if (cameraPath) row.flickerRatio = refFlicker > 0.0 ? flicker / refFlicker : 0.0;
    tools::destroyModuleSession(ctx, session);
    std::printf("gi-bench: %-40s %9.2f ms  MSE %.4e  relMSE %.4e  SSIM %.4f\n", config.label.c_str(), row.totalMs,
                row.final.mse, row.final.relMse, row.final.ssim);
    std::fflush(stdout);
    rows.push_back(row);
  }

  // Equal-error speed-up against raw MC measured in the same run.
  std::vector<double> rawTimes, rawErrors, rawIndirectErrors;
  for (const Row& r : rows)
    if (r.config.settings.method == gi::Method::Raw && !r.config.settings.raw.temporalAccumulation) {
      rawTimes.push_back(r.totalMs);
      rawErrors.push_back(r.final.mse);
      rawIndirectErrors.push_back(r.indirect.mse);
    }
  double c = metrics::fitInverseLaw(rawTimes, rawErrors);
  double cIndirect = metrics::fitInverseLaw(rawTimes, rawIndirectErrors);
  for (Row& r : rows) {
    r.speedup = metrics::equalErrorSpeedup(c, r.totalMs, r.final.mse);
    r.speedupIndirect = metrics::equalErrorSpeedup(cIndirect, r.totalMs, r.indirect.mse);
  }

  fs::path csvPath = dir / "results.csv";
  std::ofstream csv(csvPath);
  csv << "scene,method,settings,spp,frames,total_ms,pass_ms,rays,mrays_per_s,ray_efficiency,mse,relmse,psnr,ssim,"
         "mse_indirect,relmse_indirect,psnr_indirect,ssim_indirect,memory_bytes,equal_error_speedup,flicker_ratio,"
         "hash_occupancy,hash_failed_inserts,hash_mean_probe,hash_max_probe,hash_evicted,traced_spp,equal_error_speedup_indirect,"
         "hash_stale_resets,move_recovery_frames,move_steady_mse_indirect,label,image\n";
  for (const Row& r : rows) {
    std::string passes;
    for (const std::string& name : r.passOrder) {
      char item[128];
      std::snprintf(item, sizeof(item), "%s%s:%.3f", passes.empty() ? "" : ";", name.c_str(), r.passMs.at(name));
      passes += item;
    }
    double mrays = r.traceMs > 0.0 ? r.rays / (r.traceMs * 1e3) : 0.0;
    char line[4096];
    std::snprintf(line, sizeof(line),
                  "%s,%s,\"%s\",%u,%u,%.4f,%s,%.0f,%.4f,%.4f,%.6e,%.6e,%.4f,%.6f,%.6e,%.6e,%.4f,%.6f,%llu,%.4f,%s,%.4f,%u,%.3f,%u,%u,%u,%.4f,%u,%d,%.6e,\"%s\",%s\n",
                  sceneName.c_str(), gi::methodName(r.config.settings.method), r.config.settingsText.c_str(), r.config.spp,
                  frames, r.totalMs, passes.c_str(), r.rays, mrays, bare.mraysPerSecond() > 0 ? mrays / bare.mraysPerSecond() : 0.0,
                  r.final.mse, r.final.relMse, r.final.psnr, r.final.ssim, r.indirect.mse, r.indirect.relMse,
                  r.indirect.psnr, r.indirect.ssim, (unsigned long long)r.memory, r.speedup,
                  r.flickerRatio >= 0.0 ? std::to_string(r.flickerRatio).c_str() : "", double(r.hash.occupancy()),
                  r.hash.failedInserts, double(r.hash.meanProbe), r.hash.maxProbe, r.hash.evicted, r.tracedSpp,
                  r.speedupIndirect, r.hash.staleResets, r.recoveryFrames, r.steadyMse, r.config.label.c_str(),
                  imagePath(r.config.label).c_str());
    csv << line;
  }
  csv.close();
  if (series.is_open()) series.close();  // complete on disk before plot_bench.py reads it
  std::ofstream meta(dir / "run.txt");
  meta << "scene " << scene.sourcePath << "\ndevice " << ctx.properties.deviceName << "\nsize " << width << "x" << height
       << "\nmax_bounces " << bounces << "\nreference " << (args.has("reference") ? args.values["reference"] : key)
       << "\nreference_final "
       << (args.has("reference") ? fs::absolute(args.values["reference"]) : fs::absolute(referencePath(dir, key, gbufferPrimary, "final"))).string()
       << "\nreference_spp " << refSpp << "\nframes " << frames << "\nwarmup " << warmup
       << "\ntraversal " << engine::traversalName(ctx.traversal) << "\nbare_mrays_per_s " << bare.mraysPerSecond()
       << "\nhistory_format " << history << "\n";
  // Each configuration's programs were dispatched once, empty, before its first frame (tools::warmModulePrograms):
  // no frame's timing includes a compile. The sums are those first dispatches' wall time.
  for (const std::string& w : programsWarmed) meta << "programs_warmed_before_frames " << w << "\n";
  meta.close();
  std::printf("gi-bench: wrote %s\n", csvPath.c_str());
  std::fflush(stdout);

  uint32_t messages = ctx.validationMessages();
  engine::destroySceneGpu(ctx, sceneGpu);
  engine::destroyContext(ctx);
  if (!ok) return 1;
  if (!args.has("no-plots")) {
    std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string cmd = python + " \"" GI_SOURCE_DIR "/tools/plot_bench.py\" \"" + dir.string() + "\"";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "gi-bench: plot_bench.py failed; results.csv is complete\n");
  }
  if (messages > 0) {
    std::fprintf(stderr, "gi-bench: %u Vulkan validation message(s)\n", messages);
    return 3;
  }
  return 0;
}
