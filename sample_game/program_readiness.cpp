#include "program_readiness.h"

#include <chrono>

#include "gi/scene.h"
#include "second_device.h"

namespace demo {
namespace {

// The stand-in module on a second device: a one-triangle scene whose facts
// (what the programs are specialised on) are the real scene's, the real
// module's G-buffer and output formats, and `target`'s programs dispatched empty.
std::string warmOnSecondDevice(const engine::Context& ctx, const gi::ModuleDesc& desc, const gi::Settings& target) {
  engine::SecondDevice dev;
  std::string error;
  if (!engine::createSecondDevice(ctx, dev, error)) return error;
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  const uint32_t indices[3] = {0, 1, 2};
  const gi::PrimitiveDesc primitive{0, 3, 0, 3, 0};
  gi::MeshDesc mesh;
  mesh.positions = positions;
  mesh.normals = normals;
  mesh.vertexCount = 3;
  mesh.indices = indices;
  mesh.indexCount = 3;
  mesh.primitives = std::span(&primitive, 1);
  const gi::MaterialDesc material;
  const gi::InstanceDesc instance;
  gi::SceneContents contents;
  contents.meshes = std::span(&mesh, 1);
  contents.materials = std::span(&material, 1);
  contents.instances = std::span(&instance, 1);
  gi::SceneCreateDesc sceneDesc;
  sceneDesc.getInstanceProcAddr = desc.getInstanceProcAddr;
  sceneDesc.instance = desc.instance;
  sceneDesc.physicalDevice = desc.physicalDevice;
  sceneDesc.device = dev.device;
  // Built as the engine builds the demo's scenes (engine/scene_gpu.cpp): for the traversal that runs, so
  // that set 0's layout, and with it the compiled programs, match.
  sceneDesc.traversal = desc.scene.traversal;
  gi::Scene* scene = nullptr;
  gi::Module* module = nullptr;
  auto fail = [&](const std::string& what) {
    gi::destroy(module);
    gi::destroyScene(scene);
    engine::destroySecondDevice(dev);
    return what;
  };
  const char* const notBegun = "the second device's command buffer could not be begun";
  VkCommandBuffer cmd = engine::beginSecond(dev);
  if (!cmd) return fail(notBegun);
  if (gi::Error e = gi::createScene(sceneDesc, contents, cmd, scene)) return fail(e.message);
  if (engine::submitAndWaitSecond(dev, cmd) != VK_SUCCESS) return fail("the stand-in scene's upload failed");
  if (gi::Error e = gi::finishSceneUpload(scene)) return fail(e.message);
  gi::ModuleDesc standIn = desc;
  standIn.device = dev.device;
  standIn.width = standIn.height = 8;
  standIn.maxWidth = standIn.maxHeight = 0;
  standIn.timestamps = false;
  standIn.debugLabels = false;
  standIn.pipelineCache = VK_NULL_HANDLE;
  standIn.enabledFeatures = nullptr;
  // Every fact of the real scene (what the programs are specialised on and what the method's plan reads),
  // with the stand-in's own set 0, made by the same code as the real one's: the same layout.
  const gi::SceneDesc own = gi::sceneDesc(scene);
  standIn.scene.layout = own.layout;
  standIn.scene.set = own.set;
  standIn.scene.hasComputeBvh = own.hasComputeBvh;
  if (gi::Error e = gi::create(standIn, target, module)) return fail(e.message);
  cmd = engine::beginSecond(dev);
  if (!cmd) return fail(notBegun);
  if (gi::Error e = gi::recordProgramWarmup(module, target, cmd)) return fail(e.message);
  if (engine::submitAndWaitSecond(dev, cmd) != VK_SUCCESS) return fail("the warm-up's submission failed");
  gi::finishProgramWarmup(module);
  return fail("");
}

}  // namespace

bool compilesAtFirstDispatch(const engine::Context& ctx) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &driver;
  vkGetPhysicalDeviceProperties2(ctx.physicalDevice, &props);
  return driver.driverID == VK_DRIVER_ID_MESA_LLVMPIPE;
}

void startReadying(ProgramReadiness& r, const engine::Context& ctx, gi::Module* module, const gi::ModuleDesc& desc,
                   const gi::Settings& target) {
  r.busy = true;
  r.finished = false;
  r.target = target;
  r.error.clear();
  const bool secondDevice = compilesAtFirstDispatch(ctx);
  r.worker = std::thread([&r, &ctx, module, desc, target, secondDevice] {
    const auto start = std::chrono::steady_clock::now();
    if (gi::Error e = gi::preparePrograms(module, target)) r.error = e.message;
    if (r.error.empty() && secondDevice) r.error = warmOnSecondDevice(ctx, desc, target);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.finished = true;
  });
}

bool collectReady(ProgramReadiness& r) {
  if (!r.busy || !r.finished) return false;
  r.worker.join();
  r.busy = false;
  return true;
}

void joinReadying(ProgramReadiness& r) {
  if (r.worker.joinable()) r.worker.join();
  r.busy = false;
}

}  // namespace demo
