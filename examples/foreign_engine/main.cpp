// A foreign engine: a separate program that knows the GI module only by its
// public headers. It creates its own Vulkan device through the system loader,
// loads glTF with its own loader, keeps its own vertex and index buffers,
// rasterises its own G-buffer (octahedral RG16 normals, sRGB albedo,
// hardware reversed-Z depth) with a projection jittered every frame, hands
// the scene to the module (gi::createScene) and the G-buffer to each frame
// (gi::recordFrame), three frames in flight. Everything the module reads is
// in SHADER_READ_ONLY_OPTIMAL, and the engine keeps the outputs in that
// layout and samples them in a fragment shader (present_pass.h). It reports
// the mean demodulated indirect light over its frames, which the tests
// compare with gi-render's.
//
//   foreign_engine --scene FILE.gltf [--method NAME] [--size WxH] [--frames N] [--max-bounces B] [--view NAME] [--meshes device|cpu] [--out FILE.pfm] [--validation]
//
// Exit status: 0 when the frames ran and validation (with --validation)
// reported nothing; 1 otherwise; 2 on a Vulkan failure.
#include <vulkan/vulkan.h>

#include <gi/catalogue.h>
#include <gi/gi.h>
#include <gi/scene.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "gbuffer_pass.h"
#include "gltf_scene.h"
#include "present_pass.h"
#include "vulkan_host.h"

namespace {

struct Options {
  std::string scene;
  gi::Method method = gi::Method::Raw;
  uint32_t width = 96, height = 96, frames = 16;
  bool validation = false;
  std::string out;  // the frames' mean indirect light (or debug view) as a .pfm, if given
  gi::DebugView view = gi::DebugView::None;
  uint32_t maxBounces = 0;     // 0: gi::Settings' default
  bool deviceMeshes = true;    // the G-buffer's own vertex/index buffers (false: the loaded CPU arrays)
  bool packedOutputs = false;  // the outputs in this engine's HDR format, B10G11R11 (false: half floats)
};

bool parseOptions(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
    if (arg == "--validation") {
      o.validation = true;
    } else if (arg == "--view" && value) {
      bool found = false;
      for (const gi::DebugViewInfo& v : gi::debugViewCatalogue())
        if (v.name == std::string(value)) o.view = v.view, found = true;
      if (!found) return std::fprintf(stderr, "foreign_engine: unknown debug view %s\n", value), false;
      ++i;
    } else if (arg == "--meshes" && value && (std::string(value) == "device" || std::string(value) == "cpu")) {
      o.deviceMeshes = std::string(argv[++i]) == "device";
    } else if (arg == "--outputs" && value && (std::string(value) == "half" || std::string(value) == "packed")) {
      o.packedOutputs = std::string(argv[++i]) == "packed";
    } else if (arg == "--out" && value) {
      o.out = argv[++i];
    } else if (arg == "--scene" && value) {
      o.scene = argv[++i];
    } else if (arg == "--method" && value) {
      if (!gi::methodFromName(value, o.method))
        return std::fprintf(stderr, "foreign_engine: unknown method %s\n", value), false;
      ++i;
    } else if (arg == "--size" && value && std::sscanf(value, "%ux%u", &o.width, &o.height) == 2 && o.width &&
               o.height) {
      ++i;
    } else if (arg == "--max-bounces" && value && std::sscanf(value, "%u", &o.maxBounces) == 1 && o.maxBounces > 0) {
      ++i;
    } else if (arg == "--frames" && value && std::sscanf(value, "%u", &o.frames) == 1 && o.frames > 0) {
      ++i;
    } else {
      std::fprintf(stderr,
                   "usage: foreign_engine --scene FILE.gltf [--method NAME] [--size WxH] [--frames N] [--max-bounces "
                   "B] [--view NAME] [--meshes device|cpu] [--outputs half|packed] [--out FILE.pfm] [--validation]\n");
      return false;
    }
  }
  if (o.scene.empty()) return std::fprintf(stderr, "foreign_engine: --scene is required\n"), false;
  return true;
}

// The engine's camera for frame `frame`: reversed Z with an infinite far
// plane, y down, shifted by a Halton (2, 3) sub-pixel jitter as TAA would.
struct FrameCamera {
  glm::mat4 viewFromWorld, clipFromView, unjitteredClipFromView;
};

float halton(uint32_t i, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  for (; i > 0; i /= base) {
    f /= float(base);
    r += f * float(i % base);
  }
  return r;
}

FrameCamera frameCamera(const foreign::Camera& camera, VkExtent2D extent, uint32_t frame) {
  FrameCamera c;
  c.viewFromWorld = glm::inverse(camera.worldFromView);
  const float tanHalf = std::tan(0.5f * camera.yfov), aspect = float(extent.width) / float(extent.height);
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f / (aspect * tanHalf);
  p[1][1] = -1.0f / tanHalf;  // y down
  p[2][3] = -1.0f;            // clip w = −z_view
  p[3][2] = camera.znear;     // depth = znear / −z_view: 1 at the near plane, 0 at infinity
  c.unjitteredClipFromView = p;
  const glm::vec2 jitter(halton(frame + 1, 2) - 0.5f, halton(frame + 1, 3) - 0.5f);  // pixels
  p[2][0] = -2.0f * jitter.x / float(extent.width);                                  // ndc += 2 · jitter / size
  p[2][1] = -2.0f * jitter.y / float(extent.height);
  c.clipFromView = p;
  return c;
}

gi::CameraDesc cameraDesc(const FrameCamera& c) {
  gi::CameraDesc d;
  std::memcpy(d.viewFromWorld, &c.viewFromWorld[0][0], sizeof(d.viewFromWorld));  // GLM is column-major too
  std::memcpy(d.clipFromView, &c.clipFromView[0][0], sizeof(d.clipFromView));
  return d;
}

gi::InstanceDesc instanceDesc(const foreign::Instance& inst) {
  gi::InstanceDesc d;
  d.mesh = inst.mesh;
  std::memcpy(d.worldFromObject, &inst.worldFromObject[0][0], sizeof(d.worldFromObject));
  return d;
}

// Portable float map, rgb: rows bottom to top, little-endian (scale −1).
bool writePfm(const std::string& path, VkExtent2D extent, const std::vector<float>& rgb) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  std::fprintf(f, "PF\n%u %u\n-1.0\n", extent.width, extent.height);
  for (uint32_t y = extent.height; y-- > 0;)
    std::fwrite(&rgb[size_t(y) * extent.width * 3], sizeof(float), extent.width * 3, f);
  return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parseOptions(argc, argv, options)) return 1;
  foreign::SceneFile file;
  std::string error;
  if (!foreign::loadScene(options.scene, file, error)) {
    std::fprintf(stderr, "foreign_engine: %s\n", error.c_str());
    return 1;
  }
  example::Host h;
  example::createHost(options.validation, h);
  const VkExtent2D extent{options.width, options.height};

  // --- the scene, handed to the module in its terms ---------------------------
  // The G-buffer pass owns the vertex and index buffers; the module reads its
  // meshes from them (or, with --meshes cpu, from the loaded arrays).
  foreign::GBufferPass gbuffer;
  foreign::createGBufferPass(h, file, extent, gbuffer);
  std::vector<gi::MeshDesc> meshes;
  if (options.deviceMeshes) {
    meshes = foreign::deviceMeshes(h, gbuffer);
  } else {
    for (const foreign::Mesh& m : file.meshes) {
      gi::MeshDesc d;
      d.positions = &m.positions[0].x;
      d.normals = &m.normals[0].x;
      d.vertexCount = uint32_t(m.positions.size());
      d.indices = m.indices.data();
      d.indexCount = uint32_t(m.indices.size());
      d.primitives = m.primitives;
      meshes.push_back(d);
    }
  }
  std::vector<gi::InstanceDesc> instances;
  for (const foreign::Instance& inst : file.instances) instances.push_back(instanceDesc(inst));
  gi::SceneContents contents;
  contents.meshes = meshes;
  contents.materials = file.materials;
  contents.lights = file.lights;
  contents.instances = instances;
  gi::SceneCreateDesc sceneCreate;
  sceneCreate.getInstanceProcAddr = vkGetInstanceProcAddr;  // the system loader's
  sceneCreate.instance = h.instance;
  sceneCreate.physicalDevice = h.physical;
  sceneCreate.device = h.device;
  sceneCreate.traversal = gi::Traversal::Compute;  // the device has no ray-tracing extensions
  gi::Scene* scene = nullptr;
  gi::Error sceneError;
  example::submitOnce(h, [&](VkCommandBuffer cmd) { sceneError = gi::createScene(sceneCreate, contents, cmd, scene); });
  // That command buffer has completed: device meshes were read back, and the
  // scene is built from them into a second one.
  if (!sceneError) example::submitOnce(h, [&](VkCommandBuffer cmd) { sceneError = gi::finishSceneUpload(scene, cmd); });
  if (sceneError) {
    std::fprintf(stderr, "foreign_engine: %s: %s\n", options.scene.c_str(), sceneError.message.c_str());
    gi::destroyScene(scene);
    foreign::destroyGBufferPass(h, gbuffer);
    example::destroyHost(h);
    return 1;
  }
  gi::finishSceneUpload(scene);  // frees the build's staging

  // --- the module ----------------------------------------------------------------
  using foreign::kFramesInFlight;
  gi::ModuleDesc desc;
  desc.getInstanceProcAddr = vkGetInstanceProcAddr;
  desc.instance = h.instance;
  desc.physicalDevice = h.physical;
  desc.device = h.device;
  desc.width = extent.width;
  desc.height = extent.height;
  desc.framesInFlight = kFramesInFlight;
  desc.scene = gi::sceneDesc(scene);
  desc.gbuffer = foreign::gbufferDesc();
  desc.outputLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;  // the layout this engine samples them in
  if (options.packedOutputs) desc.outputFormat = VK_FORMAT_B10G11R11_UFLOAT_PACK32;  // where the device stores to it
  gi::Settings settings;
  settings.method = options.method;
  settings.debugView = options.view;
  if (options.maxBounces) settings.maxBounces = options.maxBounces;
  gi::Module* module = nullptr;
  if (gi::Error e = gi::create(desc, settings, module)) {
    std::fprintf(stderr, "foreign_engine: gi::create: %s\n", e.message.c_str());
    return 1;
  }
  // The outputs hold light × preExposure: scale it so typical light is near 1.
  const float preExposure = 1.0f / desc.scene.typicalRadiance;
  const gi::OutputScales scales = gi::outputScales(settings, preExposure);  // 1 for debug views that are pictures
  const float scale = options.view == gi::DebugView::None ? scales.indirect : scales.composite;
  const gi::Outputs outputs = gi::outputs(module);  // a debug view is shown in the composite
  foreign::PresentPass present;
  foreign::createPresentPass(
      h, extent, options.view == gi::DebugView::None ? outputs.indirectView : outputs.compositeView, present);

  VkCommandBuffer cmds[kFramesInFlight];
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = h.pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = kFramesInFlight;
  EXAMPLE_CHECK(vkAllocateCommandBuffers(h.device, &alloc, cmds));
  VkFence fences[kFramesInFlight];
  example::Buffer readback[kFramesInFlight];
  const size_t pixels = size_t(extent.width) * extent.height;
  for (uint32_t i = 0; i < kFramesInFlight; ++i) {
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    EXAMPLE_CHECK(vkCreateFence(h.device, &fenceInfo, nullptr, &fences[i]));
    readback[i] = example::createBuffer(h, pixels * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT);  // rgba32f
  }

  // --- frames ----------------------------------------------------------------------
  std::vector<glm::dvec3> frameMeans;
  std::vector<float> meanImage;        // rgb, W/(sr·m²), rows top to bottom: the frames' mean
  auto collect = [&](uint32_t slot) {  // the mean indirect light of the frame that used `slot`
    const float* texels = static_cast<const float*>(readback[slot].mapped);  // radiance: the present pass divided
    glm::dvec3 sum(0.0);
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) sum[c] += texels[4 * p + size_t(c)];
    frameMeans.push_back(sum / double(pixels));
    meanImage.resize(pixels * 3, 0.0f);
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) meanImage[3 * p + size_t(c)] += texels[4 * p + size_t(c)] / float(options.frames);
  };
  glm::mat4 previousMotionClip(0.0f);
  for (uint32_t frame = 0; frame < options.frames; ++frame) {
    const uint32_t slot = frame % kFramesInFlight;
    EXAMPLE_CHECK(vkWaitForFences(h.device, 1, &fences[slot], VK_TRUE, UINT64_MAX));
    if (frame >= kFramesInFlight) collect(slot);
    EXAMPLE_CHECK(vkResetFences(h.device, 1, &fences[slot]));
    const FrameCamera cam = frameCamera(file.camera, extent, frame);
    const FrameCamera previous = frameCamera(file.camera, extent, frame > 0 ? frame - 1 : 0);
    const glm::mat4 motionClip = cam.unjitteredClipFromView * cam.viewFromWorld;
    foreign::FrameUniforms uniforms{cam.clipFromView * cam.viewFromWorld, motionClip,
                                    frame > 0 ? previousMotionClip : motionClip, file.camera.worldFromView[3],
                                    glm::vec4(float(extent.width), float(extent.height), 0.0f, 0.0f)};
    previousMotionClip = motionClip;

    VkCommandBuffer cmd = cmds[slot];
    EXAMPLE_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    EXAMPLE_CHECK(vkBeginCommandBuffer(cmd, &begin));
    foreign::recordGBuffer(cmd, gbuffer, slot, uniforms);
    gi::FrameInputs inputs{foreign::gbufferViews(gbuffer), cameraDesc(cam), cameraDesc(previous), frame};
    inputs.preExposure = preExposure;
    if (gi::Error e = gi::recordFrame(module, cmd, inputs)) {
      std::fprintf(stderr, "foreign_engine: gi::recordFrame: %s\n", e.message.c_str());
      return 1;
    }
    // The output sampled in a fragment shader: the module's last barrier made it visible, and the next
    // recordFrame waits for this read before writing it again.
    foreign::recordPresent(cmd, present, slot, scale, readback[slot]);
    EXAMPLE_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    EXAMPLE_CHECK(vkQueueSubmit(h.queue, 1, &submit, fences[slot]));
  }
  EXAMPLE_CHECK(vkDeviceWaitIdle(h.device));
  for (uint32_t f = options.frames > kFramesInFlight ? options.frames - kFramesInFlight : 0; f < options.frames; ++f)
    collect(f % kFramesInFlight);

  const gi::FrameStats stats = gi::stats(module);
  std::printf("last frame: %llu rays, %u sanitized pixels, %.2f ms\n", (unsigned long long)stats.raysTraced,
              stats.sanitized, stats.totalMs);
  glm::dvec3 mean(0.0), variance(0.0);
  for (const glm::dvec3& m : frameMeans) mean += m / double(frameMeans.size());
  for (const glm::dvec3& m : frameMeans)
    variance += (m - mean) * (m - mean) / double(std::max<size_t>(frameMeans.size() - 1, 1));
  const glm::dvec3 standardError = glm::sqrt(variance / double(frameMeans.size()));
  std::printf(
      "%s: %s, %ux%u, %u frames (jittered, %u in flight), %zu triangles' scene through gi::createScene from %s\n",
      options.scene.c_str(), gi::methodCatalogue()[size_t(options.method)].name, extent.width, extent.height,
      options.frames, kFramesInFlight, size_t(gi::sceneInfo(scene).triangles),
      options.deviceMeshes ? "the G-buffer's device buffers" : "CPU arrays");
  std::printf("mean %s: %.6f %.6f %.6f\n", options.view == gi::DebugView::None ? "indirect" : "composite", mean.x,
              mean.y, mean.z);
  std::printf("standard error: %.6f %.6f %.6f\n", standardError.x, standardError.y, standardError.z);
  std::printf("outputs: %s\n", options.packedOutputs ? "B10G11R11 (packed)" : "RGBA16F");

  if (!options.out.empty() && !writePfm(options.out, extent, meanImage)) {
    std::fprintf(stderr, "foreign_engine: cannot write %s\n", options.out.c_str());
    return 1;
  }

  for (uint32_t i = 0; i < kFramesInFlight; ++i) {
    vkDestroyFence(h.device, fences[i], nullptr);
    example::destroyBuffer(h, readback[i]);
  }
  foreign::destroyPresentPass(h, present);
  gi::destroy(module);
  gi::destroyScene(scene);
  foreign::destroyGBufferPass(h, gbuffer);
  const uint32_t messages = h.validationMessages;
  example::destroyHost(h);
  std::printf("validation messages: %u\n", messages);
  return messages == 0 ? 0 : 1;
}
