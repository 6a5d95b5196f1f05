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
  engine::Sky sky;  // --sky; black by default
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
    if (colon == std::string::npos || end != v.c_str() + colon || !gi::methodFromName(v.substr(colon + 1), o.switchTo)) {
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
  if (!engine::writeImage(path.string(), demo::readDisplay(ctx, display), error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return false;
  }
  if (announce) std::printf("screenshot %s\n", path.string().c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!parseOptions(argc, argv, o, error)) return usageError(error);
  if (o.help) {
    std::printf("%s", cli::usage("sample_game", "[options]", kOptions).c_str());
    return 0;
  }
  if (o.headless && o.frames == 0) o.frames = o.benchmark ? o.benchmark : 30;
  if (o.benchmark) o.frames = o.benchmark;
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) {
    std::fprintf(stderr, "sample_game: %s: cannot create the output directory (%s)\n", o.out.string().c_str(),
                 ec.message().c_str());
    return 1;
  }

  engine::Scene scene;
  if (!engine::loadSceneForRendering(o.scene, scene, error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return 1;
  }
  engine::ContextDesc contextDesc;
  contextDesc.validation = o.validation;
  contextDesc.synchronizationValidation = o.syncValidation;
  contextDesc.traversal = o.traversal;
  if (!o.headless) {
    if (engine::windowInstanceExtensions(contextDesc.instanceExtensions, error)) contextDesc.swapchain = true;
    else {
      std::printf("sample_game: %s; running headless\n", error.c_str());
      o.headless = true;
      if (o.frames == 0) o.frames = 30;
    }
  }
  if (o.headless)
    std::printf("sample_game: no display: running headless, writing the walkthrough's frames (PNG) and benchmark.csv to %s\n",
                o.out.string().c_str());
  engine::Context ctx;
  if (!engine::createContext(contextDesc, ctx, error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return 1;
  }
  engine::SceneGpu sceneGpu;
  scene.sky = o.sky;
  scene.lightSampler = o.lightSampler;
  scene.lightTreeCut = o.lightTreeCut;
  const engine::SceneAnimation animation = engine::makeSceneAnimation(scene);
  engine::markAnimatedInstancesMovable(animation, scene);  // the overlay may start the animation at any time
  engine::createSceneGpu(ctx, scene, sceneGpu);
  tools::ModuleSession session;
  if (!tools::createModuleSession(ctx, sceneGpu, {o.width, o.height}, o.settings, session, error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return 2;
  }
  engine::Window window;
  if (!o.headless && !engine::createWindow(ctx, o.windowWidth, o.windowHeight, "GI module: sample game", window, error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return 1;
  }
  const VkExtent2D displaySize{o.windowWidth, o.windowHeight};
  // One display image per frame in flight: a finished frame's image is read
  // (saved) while the next frame draws into the other.
  demo::DisplayPass displays[engine::kFramesInFlight];
  for (demo::DisplayPass& d : displays) d = demo::createDisplayPass(ctx, displaySize, gi::outputs(session.module).compositeView);
  engine::FrameSlots headless;  // the window has its own
  if (o.headless) headless = engine::createFrameSlots(ctx);

  ImGui::CreateContext();
  ImGui::StyleColorsDark();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
  if (!o.headless) ImGui_ImplGlfw_InitForVulkan(window.handle, true);
  demo::OverlayRenderer overlay = demo::createOverlayRenderer(ctx, demo::kDisplayFormat);

  demo::OverlayState ui;
  ui.animate = o.animate;
  ui.walkthrough = o.walkthrough;
  ui.budgetMode = o.budgetMs > 0.0f;
  if (ui.budgetMode) ui.budget.targetMs = o.budgetMs;
  const float extent = scene.worldBounds().extent();
  demo::Walkthrough path{demo::freeCameraFrom(scene.cameras[0]), extent};
  demo::FreeCamera freeCamera = path.start;
  gi::Settings settings = o.settings, applied = o.settings;  // what the panel edits, what the module runs

  // Settings whose programs are not ready are readied off the frame first (program_readiness.h).
  demo::ProgramReadiness readiness;
  const gi::ModuleDesc moduleDesc = tools::moduleDesc(ctx, sceneGpu, {o.width, o.height});
  auto apply = [&](const gi::Settings& wanted) {
    if (gi::Error e = gi::validate(wanted)) {
      ui.settingsError = e.message;  // the module keeps running what it had
      settings = applied;
      return;
    }
    ui.settingsError.clear();
    if (!o.switchInFrame && !gi::programsPrepared(session.module, wanted)) {
      if (!readiness.busy) demo::startReadying(readiness, ctx, session.module, moduleDesc, wanted);
      ui.compiling = gi::methodName(wanted.method);  // the newest wish is applied when the worker is done
      return;
    }
    if (gi::Error e = gi::setSettings(session.module, wanted)) {
      ui.settingsError = e.message;
      settings = applied;
    } else {
      applied = wanted;
    }
  };
  demo::FrameFacts factsOfFrame[engine::kFramesInFlight];  // what each frame in flight ran, for its CSV row

  demo::FrameLog log;
  bool logging = o.headless || o.benchmark > 0;
  if (logging && !demo::openFrameLog(log, (o.out / "benchmark.csv").string(), error)) {
    std::fprintf(stderr, "sample_game: %s\n", error.c_str());
    return 1;
  }

  Keys keys;
  bool previousP = false, previousF12 = false, screenshotPending = false;
  glm::dvec2 previousMouse(0.0);
  gpu::GpuCamera previousCamera{};
  using Clock = std::chrono::steady_clock;
  Clock::time_point start = Clock::now(), lastFrame = start;
  double cpuMs = 0.0, moduleMsSum = 0.0, seconds = 0.0, lastSeconds = 0.0;
  uint32_t measured = 0, frame = 0;
  const bool fixedStep = o.headless || o.benchmark > 0;  // a deterministic path: 30 frames per walkthrough second

  // Once frame `completed` has finished on the GPU: its numbers and the CSV row.
  auto completedFrame = [&](uint32_t completed) {
    gi::FrameStats stats;
    if (!gi::frameStats(session.module, completed, stats)) stats = gi::stats(session.module);
    double gbufferMs = 0.0;
    for (const engine::PassTime& p : engine::readPassTimes(ctx, tools::gbufferTimer(session, completed))) gbufferMs += p.ms;
    demo::recordFrameNumbers(ui, stats, gbufferMs, cpuMs);
    if (logging)
      demo::writeFrameRow(log, completed, lastSeconds, cpuMs, gbufferMs, stats, factsOfFrame[completed % engine::kFramesInFlight]);
    moduleMsSum += stats.totalMs;
    ++measured;
    return stats;
  };
  // Frames are recorded two ahead, windowed and headless: a frame's numbers,
  // and headless its PNG, are taken once the frame two later begins.
  const uint32_t framesInFlight = engine::kFramesInFlight;
  auto saveFrame = [&](uint32_t completed) {
    char name[64];
    std::snprintf(name, sizeof(name), "frame_%05u.png", completed);
    return saveDisplay(ctx, displays[completed % framesInFlight], o.out / name, false);
  };

  engine::startCountingVulkanCalls();
  for (; o.frames == 0 || frame < o.frames; ++frame) {
    const engine::VulkanCallCounts callsBefore = engine::vulkanCallCounts();
    uint32_t image = 0;
    VkCommandBuffer frameCmd = VK_NULL_HANDLE;
    if (!o.headless) {
      if (engine::windowShouldClose(window)) break;
      if (!engine::beginWindowFrame(ctx, window, image)) {
        --frame;
        continue;
      }
      frameCmd = window.cmd;
    } else {
      engine::waitFrameSlot(ctx, headless, frame);
      frameCmd = engine::beginFrameSlot(ctx, headless, frame);
    }
    demo::DisplayPass& display = displays[frame % framesInFlight];
    // The frame recorded framesInFlight ago has completed: its numbers and the budget's next step.
    Clock::time_point now = Clock::now();
    cpuMs = std::chrono::duration<double, std::milli>(now - lastFrame).count();
    lastFrame = now;
    if (frame >= framesInFlight) {
      gi::FrameStats stats = completedFrame(frame - framesInFlight);
      if (o.headless && !o.benchmark && !saveFrame(frame - framesInFlight)) return 1;  // before this frame redraws it
      if (ui.budgetMode) {
        settings.rayBudget = applied.rayBudget = gi::updateBudget(ui.budget, stats);
        gi::setSettings(session.module, applied);
      }
    }

    // Input, camera and the moving scene.
    ImGuiIO& io = ImGui::GetIO();
    if (o.headless) {
      io.DisplaySize = ImVec2(float(displaySize.width), float(displaySize.height));
      io.DeltaTime = 1.0f / 30.0f;
    } else {
      ImGui_ImplGlfw_NewFrame();
      int ww = 1, wh = 1;
      glfwGetWindowSize(window.handle, &ww, &wh);
      io.MousePos.x *= float(displaySize.width) / float(std::max(ww, 1));  // the overlay lives in display pixels
      io.MousePos.y *= float(displaySize.height) / float(std::max(wh, 1));
      io.DisplaySize = ImVec2(float(displaySize.width), float(displaySize.height));
      io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
    }
    float dt = fixedStep ? 1.0f / 30.0f : float(cpuMs * 1e-3);
    seconds += dt;
    if (!o.headless) {
      demo::CameraInput input = pollInput(window.handle, extent, keys, previousP, previousF12, previousMouse);
      if (keys.walkthroughToggle) ui.walkthrough = !ui.walkthrough;
      if (keys.screenshot) ui.screenshotRequested = true;
      if (!ui.walkthrough) demo::updateFreeCamera(freeCamera, input, dt);
    }
    if (ui.walkthrough) freeCamera = demo::walkthroughCamera(path, seconds);
    gpu::GpuCamera camera =
        engine::makeGpuCamera(demo::toCamera(freeCamera), o.width, o.height, frame > 0 ? &previousCamera : nullptr);

    ImGui::NewFrame();
    gi::FrameStats shown = gi::stats(session.module);
    if (demo::collectReady(readiness)) {
      if (!readiness.error.empty()) std::printf("sample_game: readying %s: %s\n", gi::methodName(readiness.target.method), readiness.error.c_str());
      ui.compiling.clear();
      apply(settings);  // the newest wish: readied now, or readied next
    }
    if (frame == o.switchAt) {
      settings.method = o.switchTo;
      apply(settings);
    }
    if (demo::buildOverlay(ui, settings, shown)) apply(settings);
    factsOfFrame[frame % engine::kFramesInFlight].method = gi::methodName(applied.method);
    factsOfFrame[frame % engine::kFramesInFlight].readying = readiness.busy;
    if (ui.screenshotRequested) {
      screenshotPending = true;
      ui.screenshotRequested = false;
    }
    ImGui::Render();

    auto record = [&](VkCommandBuffer cmd) {
      if (ui.animate) {
        // The scene's tables are written in this frame's command buffer: the frame in flight keeps its own.
        engine::animateScene(animation, seconds, scene);
        engine::recordSceneTransformUpdate(ctx, cmd, scene, sceneGpu);
        if (ui.tellModuleLightsMoved) gi::invalidate(session.module, gi::Invalidate::LightsChanged);
      }
      // The module pre-exposes its light with the demo's exposure, as an engine keeps half floats in
      // range; the display applies what is left (nothing) and clamps.
      session.preExposure = ui.exposure;
      tools::recordModuleFrame(ctx, cmd, session, scene, sceneGpu, camera, frame > 0 ? previousCamera : camera, frame);
      demo::recordDisplay(ctx, cmd, display, ui.exposure / session.preExposure, session.extent);
      demo::recordOverlay(ctx, cmd, overlay, frame, *ImGui::GetDrawData(), display.image.image, display.image.view,
                          displaySize);
    };
    record(frameCmd);
    if (o.headless) engine::submitFrameSlot(ctx, headless, frame);
    else engine::endWindowFrame(ctx, window, image, display.image.image, displaySize);
    if (screenshotPending || frame == o.screenshotAt) {
      // With the overlay: once this frame has completed (its display image is not redrawn until frame + 2).
      vkQueueWaitIdle(ctx.queue);
      char name[64];
      std::snprintf(name, sizeof(name), "screenshot_%05u.png", frame);
      saveDisplay(ctx, display, o.out / name, true);
      screenshotPending = false;
    }
    previousCamera = camera;
    lastSeconds = seconds;
    factsOfFrame[frame % engine::kFramesInFlight].calls = engine::vulkanCallCounts() - callsBefore;
  }

  joinReadying(readiness);
  vkDeviceWaitIdle(ctx.device);
  cpuMs = std::chrono::duration<double, std::milli>(Clock::now() - lastFrame).count();
  for (uint32_t c = frame >= framesInFlight ? frame - framesInFlight : 0; c < frame; ++c) {
    completedFrame(c);
    if (o.headless && !o.benchmark && !saveFrame(c)) return 1;
  }
  double wall = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("frames %u in %.1f s; module %.2f ms GPU per frame (mean)", frame, wall,
              measured ? moduleMsSum / measured : 0.0);
  if (ui.budgetMode)
    std::printf("; budget mode: target %.1f ms, last frame %.2f ms, ray budget %.3g", ui.budget.targetMs,
                gi::stats(session.module).totalMs, double(settings.rayBudget));
  std::printf("\n");
  if (logging) std::printf("csv %s\n", (o.out / "benchmark.csv").string().c_str());

  demo::destroyOverlayRenderer(ctx, overlay);
  if (!o.headless) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  for (demo::DisplayPass& d : displays) demo::destroyDisplayPass(ctx, d);
  engine::destroyFrameSlots(ctx, headless);
  if (!o.headless) engine::destroyWindow(ctx, window);
  tools::destroyModuleSession(ctx, session);
  engine::destroySceneGpu(ctx, sceneGpu);
  uint32_t messages = ctx.validationMessages();
  engine::destroyContext(ctx);
  if (o.validation && messages > 0) {
    std::fprintf(stderr, "sample_game: Vulkan validation reported %u messages\n", messages);
    return 3;
  }
  return 0;
}
