// The smallest game loop that embeds the GI module: init, then per frame
// update the camera, raster the G-buffer, gi::recordFrame, composite into the
// frame, present (here: keep the last frame and write it as a PNG). Two
// frames in flight (engine/frame_slots.h), as engines run: each frame waits only for the fence of
// the frame two before it, whose numbers are then read.
//
//   embed_minimal SCENE.gltf OUT.png [FRAMES]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>

#include "camera.h"
#include "frame_slots.h"
#include "gbuffer.h"
#include "readback.h"
#include "gi/gi.h"
#include "image_io.h"
#include "scene_gpu.h"
#include "scene_loading.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: embed_minimal SCENE.gltf OUT.png [FRAMES]\n");
    return 2;
  }
  const uint32_t width = 160, height = 120, frames = argc > 3 ? uint32_t(std::atoi(argv[3])) : 8;

  // --- init: the engine's side -------------------------------------------------
  engine::Scene scene;
  std::string error;
  if (!engine::loadSceneForRendering(argv[1], scene, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  engine::ContextDesc contextDesc;
  contextDesc.validation = std::getenv("GI_VALIDATION") != nullptr;
  engine::Context ctx;
  if (!engine::createContext(contextDesc, ctx, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  engine::SceneGpu sceneGpu;
  if (!engine::createSceneGpu(ctx, scene, sceneGpu, error)) {  // set 0: what the module traces against
    std::fprintf(stderr, "%s\n", error.c_str());
    engine::destroyContext(ctx);
    return 1;
  }
  // The engine's calls report failures in `error` and do nothing once it is set: one check after a run of them.
  engine::GBuffer gbuffer = engine::createGBuffer(ctx, {width, height}, error);
  engine::GBufferPass gbufferPass = engine::createGBufferPass(ctx, sceneGpu, error);
  engine::FrameSlots frameSlots =
      engine::createFrameSlots(ctx, error);  // a command buffer and fence per frame in flight
  if (!error.empty()) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }

  // --- init: the module ----------------------------------------------------------
  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;  // the module loads its own function table through it
  desc.instance = ctx.instance;
  desc.physicalDevice = ctx.physicalDevice;
  desc.device = ctx.device;
  desc.width = width;
  desc.height = height;
  desc.scene = sceneGpu.desc;                  // set 0 and the scene's facts, from gi::sceneDesc
  desc.gbuffer = engine::moduleGBufferDesc();  // our G-buffer's formats, the glossy flag in albedo alpha
  gi::Settings settings;
  settings.method = gi::Method::Gif;  // guided filtering of 1-spp indirect light
  settings.maxBounces = 2;
  gi::Module* gi = nullptr;
  if (gi::Error e = gi::create(desc, settings, gi)) {
    std::fprintf(stderr, "gi::create: %s\n", e.message.c_str());
    return 1;
  }
  const gi::GBufferViews views{gbuffer.color[gpu::GBUFFER_NORMAL].view,   gbuffer.color[gpu::GBUFFER_ALBEDO].view,
                               gbuffer.color[gpu::GBUFFER_MATERIAL].view, gbuffer.color[gpu::GBUFFER_EMISSION].view,
                               gbuffer.color[gpu::GBUFFER_MOTION].view,   gbuffer.color[gpu::GBUFFER_VIEWZ].view};

  // --- the game loop: two frames in flight -------------------------------------
  constexpr uint32_t kFramesInFlight = engine::kFramesInFlight;  // the module's default ModuleDesc::framesInFlight
  auto printStats = [&](uint32_t completed) {
    gi::FrameStats stats;
    if (gi::frameStats(gi, completed, stats))
      std::printf("frame %u: %.2f ms GI, %llu rays\n", completed, stats.totalMs, (unsigned long long)stats.raysTraced);
  };
  gpu::GpuCamera previous{};
  for (uint32_t frame = 0; frame < frames; ++frame) {
    if (!engine::waitFrameSlot(ctx, frameSlots, frame, error)) break;
    if (frame >= kFramesInFlight) printStats(frame - kFramesInFlight);  // its fence has signalled: its numbers are in

    // Update: a slow orbit of the scene's camera around its up axis.
    engine::Camera camera = scene.cameras[0];
    float angle = 0.01f * float(frame);
    glm::mat4 turn = glm::mat4(glm::mat3(glm::vec3(std::cos(angle), 0, -std::sin(angle)), glm::vec3(0, 1, 0),
                                         glm::vec3(std::sin(angle), 0, std::cos(angle))));
    camera.worldFromView = camera.worldFromView * turn;
    gpu::GpuCamera current = engine::makeGpuCamera(camera, width, height, frame ? &previous : nullptr);

    VkCommandBuffer cmd = engine::beginFrameSlot(ctx, frameSlots, frame, error);
    if (!cmd) break;
    // Raster the G-buffer; it leaves the images in GENERAL, visible to compute (the module's contract).
    engine::recordGBuffer(ctx, cmd, gbufferPass, scene, sceneGpu, gbuffer, current, nullptr);
    // Global illumination: records passes, never submits.
    if (gi::Error e = gi::recordFrame(
            gi, cmd, {views, engine::moduleCamera(current), engine::moduleCamera(frame ? previous : current), frame})) {
      std::fprintf(stderr, "gi::recordFrame: %s\n", e.message.c_str());
      return 1;
    }
    // Composite → the frame: a game would barrier, then sample gi::outputs(gi).composite in its post chain.
    engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    if (!engine::submitFrameSlot(ctx, frameSlots, frame, error)) break;
    previous = current;
  }
  vkDeviceWaitIdle(ctx.device);
  for (uint32_t f = frames >= kFramesInFlight ? frames - kFramesInFlight : 0; f < frames; ++f) printStats(f);
  engine::destroyFrameSlots(ctx, frameSlots);

  // "Present": read the composite back and write it.
  const gi::Outputs outputs = gi::outputs(gi);  // half floats by default (ModuleDesc::outputFormat)
  engine::FloatImage image = engine::readbackRgb(ctx, outputs.composite, outputs.format, {width, height}, error);
  const bool written = error.empty() && engine::writeImage(argv[2], image, error);
  if (!written) std::fprintf(stderr, "%s\n", error.c_str());

  // --- shutdown ------------------------------------------------------------------
  vkDeviceWaitIdle(ctx.device);
  gi::destroy(gi);
  engine::destroyGBufferPass(ctx, gbufferPass);
  engine::destroyGBuffer(ctx, gbuffer);
  engine::destroySceneGpu(ctx, sceneGpu);
  uint32_t messages = ctx.validationMessages();
  engine::destroyContext(ctx);
  if (messages) std::fprintf(stderr, "%u validation messages\n", messages);
  return written && messages == 0 ? 0 : 1;
}
