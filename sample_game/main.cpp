// The walkthrough demo: a GLFW window over the default scene with the GI
// module, a free camera and a scripted walkthrough, a moving light and
// object, and a Dear ImGui overlay with every tunable. Without a display it
// runs headless and writes the walkthrough's frames as PNG plus a CSV.
//
//   sample_game [--scene FILE.gltf] [--method M] [--frames N] [--benchmark N] [--out DIR] ...
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "animation.h"
#include "camera.h"
#include "cli.h"
#include "display_pass.h"
#include "frame_log.h"
#include "free_camera.h"
#include "image_io.h"
#include "module_session.h"
#include "overlay.h"
#include "overlay_renderer.h"
#include "program_readiness.h"
#include "scene_gpu.h"
#include "scene_loading.h"
#include "settings_keys.h"
#include "vulkan_call_counts.h"
#include "window.h"

namespace fs = std::filesystem;

namespace {

// The default: the best final image per millisecond on the default scene as the demo runs it (relMSE × ms
// per frame, docs/RESULTS.md "The demo's default").
const std::string kMethodHelp = "GI method at start: " + tools::methodList() + " (default svgf)";
const cli::Option kOptions[] = {
    {"scene", "FILE.gltf", "scene to walk through (default assets/cornell_box/cornell_box.gltf)"},
    {"method", "M", kMethodHelp.c_str()},
    {"set", "KEY=V,...", "module settings at start (see gi-render --help for the keys)"},
    {"size", "WxH", "render size of the GI module (default 320x180)"},
    {"window-size", "WxH", "window and overlay size (default 960x540)"},
    {"frames", "N", "stop after N frames (default: until the window closes; 30 headless)"},
    {"benchmark", "N", "walk the scripted path for N frames, write the per-pass CSV, exit"},
    {"budget-ms", "MS", "start in budget mode holding the module's GPU time at MS"},
    {"out", "DIR", "where screenshots, headless frames and the CSV go (default sample_game_out)"},
    {"screenshot-at", "N", "also save a screenshot (with the overlay) of frame N"},
    {"headless", nullptr, "no window even if a display is available"},
    {"no-animation", nullptr, "keep the light and the object still"},
    {"still", nullptr, "a static scene: no animation and no walkthrough (the camera stays at the scene's)"},
    {"switch-at", "N:METHOD", "at frame N pick METHOD as the overlay would (its programs readied off the frame)"},
    {"switch-in-frame", nullptr, "switch methods at once, their programs compiled in the frame (for comparison)"},
    {"validation", nullptr, "enable Vulkan validation (exit status 3 if it reports anything)"},
    {"sync-validation", nullptr, "validation with its synchronization checks (hazards between commands and frames)"},
    cli::kTraversalOption,
    cli::kSkyOption,
    cli::kLightSamplerOption,
    cli::kLightTreeCutOption,
    {"help", nullptr, "show this message"},
};

struct Options {
  std::string scene = GI_DEFAULT_SCENE;
  gi::Settings settings;
  uint32_t width = 320, height = 180, windowWidth = 960, windowHeight = 540;
  uint32_t frames = 0, benchmark = 0, screenshotAt = UINT32_MAX;
  float budgetMs = 0.0f;
  fs::path out = "sample_game_out";
  engine::Traversal traversal = engine::Traversal::Auto;
  engine::Sky sky;                              // --sky; black by default
  uint32_t lightSampler = 2, lightTreeCut = 4;  // --light-sampler (gpu::LIGHT_SAMPLER_TREE), --light-tree-cut
  bool help = false;
  bool headless = false, animate = true, walkthrough = true, validation = false, syncValidation = false;
  uint32_t switchAt = UINT32_MAX;  // --switch-at: the frame, and the method then
  gi::Method switchTo = gi::Method::Svgf;
  bool switchInFrame = false;
};

int usageError(const std::string& message) {
  std::fprintf(stderr, "sample_game: %s\n\n%s", message.c_str(),
               cli::usage("sample_game", "[options]", kOptions).c_str());
  return 2;
}

bool parseOptions(int argc, char** argv, Options& o, std::string& error) {
  cli::Args args;
  if (!cli::parse(argc, argv, kOptions, args, error)) return false;
  o.help = args.has("help");
  if (args.has("scene")) o.scene = args.values["scene"];
  o.settings.method = gi::Method::Svgf;
  o.settings.maxBounces = 2;
  if (args.has("method") && !gi::methodFromName(args.values["method"], o.settings.method)) {
    error = "unknown method '" + args.values["method"] + "'";
    return false;
  }
  if (args.has("set"))
    for (const std::string& a : cli::splitList(args.values["set"]))
      if (!tools::applySetting(o.settings, a, error)) return false;
  if (gi::Error e = gi::validate(o.settings)) {
    error = e.message;
    return false;
  }
  uint32_t budget = 0, screenshot = 0;
  if (!cli::getSize(args, "size", 320, 180, o.width, o.height, error) ||
      !cli::getSize(args, "window-size", 960, 540, o.windowWidth, o.windowHeight, error) ||
      !cli::getUint(args, "frames", 0, 0, 1u << 30, o.frames, error) ||
      !cli::getUint(args, "benchmark", 0, 0, 1u << 30, o.benchmark, error) ||
      !cli::getUint(args, "budget-ms", 0, 0, 100000, budget, error) ||
      !cli::getUint(args, "screenshot-at", 0, 0, 1u << 30, screenshot, error))
    return false;
  o.budgetMs = float(budget);
  if (args.has("screenshot-at")) o.screenshotAt = screenshot;
  if (args.has("out")) o.out = args.values["out"];
  o.headless = args.has("headless") || std::getenv("DISPLAY") == nullptr || *std::getenv("DISPLAY") == '\0';
  o.animate = !args.has("no-animation") && !args.has("still");
  o.walkthrough = !args.has("still");
  o.syncValidation = args.has("sync-validation");
  o.validation = args.has("validation") || o.syncValidation || std::getenv("GI_VALIDATION") != nullptr;
  o.switchInFrame = args.has("switch-in-frame");
  if (args.has("switch-at")) {
    const std::string& v = args.values["switch-at"];
    const size_t colon = v.find(':');
    char* end = nullptr;
    const unsigned long at = std::strtoul(v.c_str(), &end, 10);
    if (colon == std::string::npos || end != v.c_str() + colon ||
        !gi::methodFromName(v.substr(colon + 1), o.switchTo)) {
      error = "--switch-at '" + v + "' is not FRAME:METHOD (methods: " + tools::methodList() + ")";
      return false;
    }
    o.switchAt = uint32_t(at);
  }
  return cli::getTraversal(args, o.traversal, error) && cli::getSky(args, o.sky, error) &&
         cli::getLightSampler(args, o.lightSampler, o.lightTreeCut, error);
}

// Keyboard and mouse for the free camera and the demo's keys, unless ImGui wants them.
struct Keys {
  bool walkthroughToggle = false, screenshot = false;
};
demo::CameraInput pollInput(GLFWwindow* w, float extent, Keys& keys, bool& previousP, bool& previousF12,
                            glm::dvec2& previousMouse) {
  demo::CameraInput in;
  in.speed = 0.25f * extent * (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4.0f : 1.0f);
  const ImGuiIO& io = ImGui::GetIO();
  glm::dvec2 mouse;
  glfwGetCursorPos(w, &mouse.x, &mouse.y);
  if (!io.WantCaptureMouse && glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS)
    in.look = glm::vec2(mouse - previousMouse);
  previousMouse = mouse;
  if (io.WantCaptureKeyboard) return in;
  auto key = [&](int k) { return glfwGetKey(w, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  in.move = {key(GLFW_KEY_D) - key(GLFW_KEY_A), key(GLFW_KEY_E) - key(GLFW_KEY_Q), key(GLFW_KEY_S) - key(GLFW_KEY_W)};
  bool p = key(GLFW_KEY_P) > 0.0f, f12 = key(GLFW_KEY_F12) > 0.0f;
  keys.walkthroughToggle = p && !previousP;
  keys.screenshot = f12 && !previousF12;
  previousP = p;
  previousF12 = f12;
  if (key(GLFW_KEY_ESCAPE) > 0.0f) glfwSetWindowShouldClose(w, GLFW_TRUE);
  return in;
}

bool saveDisplay(const engine::Context& ctx, const demo::DisplayPass& display, const fs::path& path, bool announce) {
  std::string error;
  const engine::FloatImage image = demo::readDisplay(ctx, display, error);
  if (!error.empty() || !engine::writeImage(path.string(), image, error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return false;
  }
  if (announce) std::printf("screenshot %s\n", path.string().c_str());
  return true;
}

}  // namespace

namespace {

using Clock = std::chrono::steady_clock;

// Everything the demo holds while it runs: the engine's side, the module's session, the window or the headless
// frame slots, the overlay, and the walkthrough's state.
struct Demo {
  Options o;
  engine::Scene scene;
  engine::Context ctx;
  engine::SceneGpu sceneGpu;
  engine::SceneAnimation animation;
  tools::ModuleSession session;
  gi::ModuleDesc moduleDesc;
  engine::Window window;
  VkExtent2D displaySize{};
  // One display image per frame in flight: a finished frame's image is read (saved) while the next frame
  // draws into the other.
  demo::DisplayPass displays[engine::kFramesInFlight];
  engine::FrameSlots headless;  // the window has its own
  demo::OverlayRenderer overlay;
  bool imgui = false;
  demo::OverlayState ui;
  float extent = 1.0f;
  demo::Walkthrough path;
  demo::FreeCamera freeCamera;
  gi::Settings settings, applied;  // what the panel edits, what the module runs
  // Settings whose programs are not ready are readied off the frame first (program_readiness.h).
  demo::ProgramReadiness readiness;
  demo::FrameFacts factsOfFrame[engine::kFramesInFlight];  // what each frame in flight ran, for its CSV row
  demo::FrameLog log;
  bool logging = false;
  bool sceneMoved = false;  // last frame's scene moved: a pause holds it once (engine::recordSceneHold)
  // Input.
  Keys keys;
  bool previousP = false, previousF12 = false, screenshotPending = false;
  glm::dvec2 previousMouse{0.0};
  // Time.
  gpu::GpuCamera previousCamera{};
  Clock::time_point start = Clock::now(), lastFrame = start;
  double cpuMs = 0.0, moduleMsSum = 0.0, seconds = 0.0, lastSeconds = 0.0;
  uint32_t measured = 0, frame = 0;
};

int fail(const std::string& error, int status) {
  std::fprintf(stderr, "sample_game: %s\n", error.c_str());
  return status;
}

// The output directory, the scene, the context (windowed when a display is there) and the module's session.
// 0, or the exit status.
int openEngine(Demo& d) {
  Options& o = d.o;
  std::string error;
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail(o.out.string() + ": cannot create the output directory (" + ec.message() + ")", 1);
  if (!engine::loadSceneForRendering(o.scene, d.scene, error)) return fail(error, 1);
  engine::ContextDesc contextDesc;
  contextDesc.validation = o.validation;
  contextDesc.synchronizationValidation = o.syncValidation;
  contextDesc.traversal = o.traversal;
  if (!o.headless) {
    if (engine::windowInstanceExtensions(contextDesc.instanceExtensions, error))
      contextDesc.swapchain = true;
    else {
      std::printf("sample_game: %s; running headless\n", error.c_str());
      o.headless = true;
      if (o.frames == 0) o.frames = 30;
    }
  }
  if (o.headless)
    std::printf(
        "sample_game: no display: running headless, writing the walkthrough's frames (PNG) and benchmark.csv to %s\n",
        o.out.string().c_str());
  if (!engine::createContext(contextDesc, d.ctx, error)) return fail(error, 1);
  d.scene.sky = o.sky;
  d.scene.lightSampler = o.lightSampler;
  d.scene.lightTreeCut = o.lightTreeCut;
  d.animation = engine::makeSceneAnimation(d.scene);
  engine::markAnimatedInstancesMovable(d.animation, d.scene);  // the overlay may start the animation at any time
  if (!engine::createSceneGpu(d.ctx, d.scene, d.sceneGpu, error)) return fail(error, 1);
  if (!tools::createModuleSession(d.ctx, d.sceneGpu, {o.width, o.height}, o.settings, d.session, error))
    return fail(error, 2);
  d.moduleDesc = tools::moduleDesc(d.ctx, d.sceneGpu, {o.width, o.height});
  return 0;
}

// The window (or the headless frame slots), the display images, ImGui and its renderer, the walkthrough and
// the frame log. 0, or the exit status.
int openPresentation(Demo& d) {
  const Options& o = d.o;
  std::string error;
  if (!o.headless &&
      !engine::createWindow(d.ctx, o.windowWidth, o.windowHeight, "GI module: sample game", d.window, error))
    return fail(error, 1);
  d.displaySize = {o.windowWidth, o.windowHeight};
  for (demo::DisplayPass& display : d.displays)
    display = demo::createDisplayPass(d.ctx, d.displaySize, gi::outputs(d.session.module).compositeView, error);
  if (o.headless) d.headless = engine::createFrameSlots(d.ctx, error);
  if (!error.empty()) return fail(error, 1);

  ImGui::CreateContext();
  d.imgui = true;
  ImGui::StyleColorsDark();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
  if (!o.headless) ImGui_ImplGlfw_InitForVulkan(d.window.handle, true);
  d.overlay = demo::createOverlayRenderer(d.ctx, demo::kDisplayFormat, error);
  if (!error.empty()) return fail(error, 1);

  d.ui.animate = o.animate;
  d.ui.walkthrough = o.walkthrough;
  d.ui.budgetMode = o.budgetMs > 0.0f;
  if (d.ui.budgetMode) d.ui.budget.targetMs = o.budgetMs;
  d.extent = d.scene.worldBounds().extent();
  d.path = demo::Walkthrough{demo::freeCameraFrom(d.scene.cameras[0]), d.extent};
  d.freeCamera = d.path.start;
  d.settings = d.applied = o.settings;
  d.logging = o.headless || o.benchmark > 0;
  if (d.logging && !demo::openFrameLog(d.log, (o.out / "benchmark.csv").string(), error)) return fail(error, 1);
  return 0;
}

// The panel's (or a switch's) wish: validated, readied off the frame when its programs are not, then applied.
void applySettings(Demo& d, const gi::Settings& wanted) {
  if (gi::Error e = gi::validate(wanted)) {
    d.ui.settingsError = e.message;  // the module keeps running what it had
    d.settings = d.applied;
    return;
  }
  d.ui.settingsError.clear();
  if (!d.o.switchInFrame && !gi::programsPrepared(d.session.module, wanted)) {
    if (!d.readiness.busy) demo::startReadying(d.readiness, d.ctx, d.session.module, d.moduleDesc, wanted);
    d.ui.compiling = gi::methodName(wanted.method);  // the newest wish is applied when the worker is done
    return;
  }
  if (gi::Error e = gi::setSettings(d.session.module, wanted)) {
    d.ui.settingsError = e.message;
    d.settings = d.applied;
  } else {
    d.applied = wanted;
  }
}

// Once frame `completed` has finished on the GPU: its numbers and the CSV row.
gi::FrameStats completedFrame(Demo& d, uint32_t completed) {
  gi::FrameStats stats;
  if (!gi::frameStats(d.session.module, completed, stats)) stats = gi::stats(d.session.module);
  double gbufferMs = 0.0;
  for (const engine::PassTime& p :
       engine::readPassTimes(d.ctx, tools::gbufferTimer(d.session, completed), d.session.error))
    gbufferMs += p.ms;
  demo::recordFrameNumbers(d.ui, stats, gbufferMs, d.cpuMs);
  d.ui.scene = gi::sceneInfo(d.sceneGpu.scene);
  if (d.logging)
    demo::writeFrameRow(d.log, completed, d.lastSeconds, d.cpuMs, gbufferMs, stats,
                        d.factsOfFrame[completed % engine::kFramesInFlight]);
  d.moduleMsSum += stats.totalMs;
  ++d.measured;
  return stats;
}

// Headless: a completed frame's display image as frame_NNNNN.png.
bool saveFrame(const Demo& d, uint32_t completed) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame_%05u.png", completed);
  return saveDisplay(d.ctx, d.displays[completed % engine::kFramesInFlight], d.o.out / name, false);
}

// Frames are recorded two ahead, windowed and headless: the frame recorded kFramesInFlight ago has completed,
// so its numbers (and headless its PNG, before this frame redraws it) are taken now, and budget mode takes
// its next step. False when the PNG could not be written or the frame's numbers could not be read (printed).
bool takeCompletedFrame(Demo& d) {
  const Clock::time_point now = Clock::now();
  d.cpuMs = std::chrono::duration<double, std::milli>(now - d.lastFrame).count();
  d.lastFrame = now;
  if (d.frame < engine::kFramesInFlight) return true;
  const uint32_t completed = d.frame - engine::kFramesInFlight;
  const gi::FrameStats stats = completedFrame(d, completed);
  if (!d.session.error.empty()) {
    fail(d.session.error, 1);  // prints it
    return false;
  }
  if (d.o.headless && !d.o.benchmark && !saveFrame(d, completed)) return false;
  if (d.ui.budgetMode) {
    d.settings.rayBudget = d.applied.rayBudget = gi::updateBudget(d.ui.budget, stats);
    gi::setSettings(d.session.module, d.applied);
  }
  return true;
}

// Input, the walkthrough or free camera, and the overlay (whose edits are applied): this frame's camera.
gpu::GpuCamera updateCameraAndOverlay(Demo& d, float dt) {
  const Options& o = d.o;
  ImGuiIO& io = ImGui::GetIO();
  if (o.headless) {
    io.DeltaTime = 1.0f / 30.0f;
  } else {
    ImGui_ImplGlfw_NewFrame();  // sets the window's size, which the display size below replaces
    int ww = 1, wh = 1;
    glfwGetWindowSize(d.window.handle, &ww, &wh);
    io.MousePos.x *= float(d.displaySize.width) / float(std::max(ww, 1));  // the overlay lives in display pixels
    io.MousePos.y *= float(d.displaySize.height) / float(std::max(wh, 1));
    io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
    demo::CameraInput input = pollInput(d.window.handle, d.extent, d.keys, d.previousP, d.previousF12, d.previousMouse);
    if (d.keys.walkthroughToggle) d.ui.walkthrough = !d.ui.walkthrough;
    if (d.keys.screenshot) d.ui.screenshotRequested = true;
    if (!d.ui.walkthrough) demo::updateFreeCamera(d.freeCamera, input, dt);
  }
  io.DisplaySize = ImVec2(float(d.displaySize.width), float(d.displaySize.height));
  if (d.ui.walkthrough) d.freeCamera = demo::walkthroughCamera(d.path, d.seconds);
  const gpu::GpuCamera camera =
      engine::makeGpuCamera(demo::toCamera(d.freeCamera), o.width, o.height, d.frame > 0 ? &d.previousCamera : nullptr);

  ImGui::NewFrame();
  gi::FrameStats shown = gi::stats(d.session.module);
  if (demo::collectReady(d.readiness)) {
    if (!d.readiness.error.empty())
      std::printf("sample_game: readying %s: %s\n", gi::methodName(d.readiness.target.method),
                  d.readiness.error.c_str());
    d.ui.compiling.clear();
    applySettings(d, d.settings);  // the newest wish: readied now, or readied next
  }
  if (d.frame == o.switchAt) {
    d.settings.method = o.switchTo;
    applySettings(d, d.settings);
  }
  if (demo::buildOverlay(d.ui, d.settings, shown)) applySettings(d, d.settings);
  demo::FrameFacts& facts = d.factsOfFrame[d.frame % engine::kFramesInFlight];
  facts.method = gi::methodName(d.applied.method);
  facts.readying = d.readiness.busy;
  if (d.ui.screenshotRequested) {
    d.screenshotPending = true;
    d.ui.screenshotRequested = false;
  }
  ImGui::Render();
  return camera;
}

// The frame's commands: the moving scene, the G-buffer and the module, the display and the overlay. False
// with `error` when the module refuses the scene's update.
bool recordDemoFrame(Demo& d, VkCommandBuffer cmd, const gpu::GpuCamera& camera, demo::DisplayPass& display,
                     std::string& error) {
  if (d.ui.animate) {
    // The scene's tables are written in this frame's command buffer: the frame in flight keeps its own.
    engine::animateScene(d.animation, d.seconds, d.scene);
    if (!engine::recordSceneTransformUpdate(d.ctx, cmd, d.scene, d.sceneGpu, error)) return false;
    if (d.ui.tellModuleLightsMoved) gi::invalidate(d.session.module, gi::Invalidate::LightsChanged);
  } else if (d.sceneMoved && !engine::recordSceneHold(cmd, d.scene, d.sceneGpu, error)) {  // paused: motion stops
    return false;
  }
  d.sceneMoved = d.ui.animate;
  // The module pre-exposes its light with the demo's exposure, as an engine keeps half floats in
  // range; the display applies what is left (nothing) and clamps.
  d.session.preExposure = d.ui.exposure;
  tools::recordModuleFrame(d.ctx, cmd, d.session, d.scene, d.sceneGpu, camera, d.frame > 0 ? d.previousCamera : camera,
                           d.frame);
  if (!d.session.error.empty()) {
    error = d.session.error;
    return false;
  }
  demo::recordDisplay(d.ctx, cmd, display, d.ui.exposure / d.session.preExposure, d.session.extent);
  return demo::recordOverlay(d.ctx, cmd, d.overlay, d.frame, *ImGui::GetDrawData(), display.image.image,
                             display.image.view, d.displaySize, error);
}

// The frames, until the window closes or the count is reached. 0, or the exit status.
int runFrames(Demo& d) {
  const Options& o = d.o;
  const bool fixedStep = o.headless || o.benchmark > 0;  // a deterministic path: 30 frames per walkthrough second
  engine::startCountingVulkanCalls();
  for (; o.frames == 0 || d.frame < o.frames; ++d.frame) {
    const engine::VulkanCallCounts callsBefore = engine::vulkanCallCounts();
    uint32_t image = 0;
    VkCommandBuffer frameCmd = VK_NULL_HANDLE;
    std::string error;
    if (!o.headless) {
      if (engine::windowShouldClose(d.window)) break;
      const engine::WindowFrame begun = engine::beginWindowFrame(d.ctx, d.window, image, error);
      if (begun == engine::WindowFrame::Skipped) {
        --d.frame;
        continue;
      }
      frameCmd = d.window.cmd;
    } else if (engine::waitFrameSlot(d.ctx, d.headless, d.frame, error)) {
      frameCmd = engine::beginFrameSlot(d.ctx, d.headless, d.frame, error);
    }
    if (!error.empty()) return fail(error, 1);
    demo::DisplayPass& display = d.displays[d.frame % engine::kFramesInFlight];
    if (!takeCompletedFrame(d)) return 1;
    const float dt = fixedStep ? 1.0f / 30.0f : float(d.cpuMs * 1e-3);
    d.seconds += dt;
    const gpu::GpuCamera camera = updateCameraAndOverlay(d, dt);
    if (!recordDemoFrame(d, frameCmd, camera, display, error)) return fail(error, 1);
    const bool submitted =
        o.headless ? engine::submitFrameSlot(d.ctx, d.headless, d.frame, error)
                   : engine::endWindowFrame(d.ctx, d.window, image, display.image.image, d.displaySize, error);
    if (!submitted) return fail(error, 1);
    if (d.screenshotPending || d.frame == o.screenshotAt) {
      // With the overlay: once this frame has completed (its display image is not redrawn until frame + 2).
      vkQueueWaitIdle(d.ctx.queue);
      char name[64];
      std::snprintf(name, sizeof(name), "screenshot_%05u.png", d.frame);
      saveDisplay(d.ctx, display, o.out / name, true);
      d.screenshotPending = false;
    }
    d.previousCamera = camera;
    d.lastSeconds = d.seconds;
    d.factsOfFrame[d.frame % engine::kFramesInFlight].calls = engine::vulkanCallCounts() - callsBefore;
  }
  return 0;
}

// The frames still in flight taken, and the summary line. 0, or the exit status.
int finishFrames(Demo& d) {
  joinReadying(d.readiness);
  vkDeviceWaitIdle(d.ctx.device);
  d.cpuMs = std::chrono::duration<double, std::milli>(Clock::now() - d.lastFrame).count();
  const uint32_t framesInFlight = engine::kFramesInFlight;
  for (uint32_t c = d.frame >= framesInFlight ? d.frame - framesInFlight : 0; c < d.frame; ++c) {
    completedFrame(d, c);
    if (d.o.headless && !d.o.benchmark && !saveFrame(d, c)) return 1;
  }
  const double wall = std::chrono::duration<double>(Clock::now() - d.start).count();
  std::printf("frames %u in %.1f s; module %.2f ms GPU per frame (mean)", d.frame, wall,
              d.measured ? d.moduleMsSum / d.measured : 0.0);
  if (d.ui.budgetMode)
    std::printf("; budget mode: target %.1f ms, last frame %.2f ms, ray budget %.3g", d.ui.budget.targetMs,
                gi::stats(d.session.module).totalMs, double(d.settings.rayBudget));
  std::printf("\n");
  if (d.logging) std::printf("csv %s\n", (d.o.out / "benchmark.csv").string().c_str());
  return 0;
}

// Everything released, in reverse order; exit status 3 when validation reported anything.
int closeDemo(Demo& d, int status) {
  if (!d.ctx.device) {  // nothing was made on a device
    engine::destroyContext(d.ctx);
    return status;
  }
  joinReadying(d.readiness);
  vkDeviceWaitIdle(d.ctx.device);
  if (d.imgui) {
    demo::destroyOverlayRenderer(d.ctx, d.overlay);
    if (!d.o.headless) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  for (demo::DisplayPass& display : d.displays) demo::destroyDisplayPass(d.ctx, display);
  engine::destroyFrameSlots(d.ctx, d.headless);
  if (!d.o.headless) engine::destroyWindow(d.ctx, d.window);
  tools::destroyModuleSession(d.ctx, d.session);
  engine::destroySceneGpu(d.ctx, d.sceneGpu);
  const uint32_t messages = d.ctx.validationMessages();
  engine::destroyContext(d.ctx);
  if (status == 0 && d.o.validation && messages > 0) {
    std::fprintf(stderr, "sample_game: Vulkan validation reported %u messages\n", messages);
    return 3;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Demo d;
  Options& o = d.o;
  std::string error;
  if (!parseOptions(argc, argv, o, error)) return usageError(error);
  if (o.help) {
    std::printf("%s", cli::usage("sample_game", "[options]", kOptions).c_str());
    return 0;
  }
  if (o.headless && o.frames == 0) o.frames = o.benchmark ? o.benchmark : 30;
  if (o.benchmark) o.frames = o.benchmark;
  int status = openEngine(d);
  if (status == 0) status = openPresentation(d);
  if (status == 0) status = runFrames(d);
  if (status == 0) status = finishFrames(d);
  return closeDemo(d, status);
}
