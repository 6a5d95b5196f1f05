// Module lifetime and the frame script. Each pass is one dispatch and the
// barrier that publishes its writes, between a timestamp pair.
#include "module.h"
#include "gpu_timer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "gi_composite.comp.h"
#include "gi_composite.comp.compute.h"
#include "gi_guidance.comp.h"
#include "gi_guidance.comp.compute.h"
#include "gi_raw_trace.comp.h"
#include "gi_raw_trace.comp.compute.h"
#include "aaf_adaptive.comp.h"
#include "aaf_adaptive.comp.compute.h"
#include "aaf_sample.comp.h"
#include "aaf_sample.comp.compute.h"
#include "gi_supersample.comp.h"
#include "gi_supersample.comp.compute.h"
#include "shared/aaf.h"

namespace gi {
namespace {

constexpr VkFormat kOutputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // fp32: radiance up to 1e6 and beyond must fit

const engine::Binding kFrameBindings[] = {
    {gpu::GI_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
    {gpu::GI_BINDING_GB_NORMAL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GB_ALBEDO, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GB_MATERIAL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GB_EMISSION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GB_MOTION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GB_VIEWZ, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_OUT_DIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_OUT_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_OUT_COMPOSITE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_HISTORY_DIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_HISTORY_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::GI_BINDING_NOISY_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_GUIDANCE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_POSITION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_DEBUG, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_AAF_PARAMS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_AAF_SUM, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_AAF_GLOSSY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_AAF_GLOSSY_EDGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
};

// The SCENE_SPEC_* specialisation values for this module's scene.
std::array<uint32_t, SCENE_SPEC_COUNT> sceneSpecialization(const Module& m) {
  return {m.desc.scene.hasEmissiveTriangles ? 1u : 0u, m.desc.scene.hasPunctualLights ? 1u : 0u,
          m.desc.scene.hasAlphaMask ? 1u : 0u};
}

bool sameView(const GBufferViews& a, const GBufferViews& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }
bool sameCamera(const gpu::GpuCamera& a, const gpu::GpuCamera& b) {
  return a.clipFromWorld == b.clipFromWorld && a.imageSize == b.imageSize;
}

Error checkDesc(const ModuleDesc& d) {
  if (d.structSize != sizeof(ModuleDesc))
    return {ErrorCode::VersionMismatch, "desc.structSize = " + std::to_string(d.structSize) + " is not this library's " +
                                            std::to_string(sizeof(ModuleDesc)) + ": built against another gi.h"};
  if (!d.instance || !d.physicalDevice || !d.device) return {ErrorCode::MissingHandle, "desc.instance, desc.physicalDevice and desc.device must be set"};
  if (!d.scene.layout || !d.scene.set) return {ErrorCode::MissingHandle, "desc.scene.layout and desc.scene.set must be set"};
  if (d.width == 0 || d.height == 0)
    return {ErrorCode::ZeroSize, "desc.width × desc.height = " + std::to_string(d.width) + "×" + std::to_string(d.height) + " has a zero side"};
  if (!(d.scene.typicalRadiance > 0.0f) || !std::isfinite(d.scene.typicalRadiance))
    return {ErrorCode::OutOfRange, "desc.scene.typicalRadiance = " + std::to_string(d.scene.typicalRadiance) +
                                       " is not a positive finite radiance"};
  if (d.width > 16384 || d.height > 16384)
    return {ErrorCode::SizeTooLarge, "desc.width × desc.height = " + std::to_string(d.width) + "×" + std::to_string(d.height) + " exceeds 16384 per side"};
  return {};
}

// The features of gi/device.h: in the chain the engine enabled, if it says
// which, else among what the device supports.
Error checkFeatures(const ModuleDesc& d) {
  const bool rayQuery = d.scene.traversal == gpu::TRAVERSAL_RAY_QUERY;
  const char* missing = nullptr;
  const char* where = "the enabled features (desc.enabledFeatures)";
  if (d.enabledFeatures) {
    missing = firstMissingFeature(*d.enabledFeatures, rayQuery);
  } else {
    VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    as.pNext = &rq;
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.pNext = rayQuery ? &as : nullptr;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.pNext = &f13;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &f12;
    vkGetPhysicalDeviceFeatures2(d.physicalDevice, &f2);
    missing = firstMissingFeature(f2, rayQuery);
    where = "the device";
  }
  if (!missing) return {};
  return {ErrorCode::MissingFeature, std::string(where) + " lacks " + missing + ", which the GI module needs" +
                                         (rayQuery ? " (with ray-query traversal)" : "") + "; see gi/device.h"};
}

engine::Image outputImage(Module& m, VkExtent2D extent) {
  return engine::createImage(m.ctx, extent, kOutputFormat,
                             VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
}

engine::Image* ownedImages(Module& m, size_t i) {
  engine::Image* all[] = {&m.direct,        &m.indirect, &m.composite, &m.historyDirect, &m.historyIndirect,
                          &m.noisyIndirect, &m.guidance, &m.position,  &m.debug,         &m.aafParams,
                          &m.aafSum,        &m.aafGlossy, &m.aafGlossyEdge};
  return i < std::size(all) ? all[i] : nullptr;
}

// The hash map sums radiance relative to the scene's typical radiance, so dim
// and bright scenes get the same fixed-point resolution (checkDesc keeps it
// positive and finite).
float radianceScale(const Module& m) { return 1.0f / m.desc.scene.typicalRadiance; }

// AAF's separate specular term runs only for aaf on a scene with glossy materials.
bool aafSpecular(const Module& m) { return m.settings.method == Method::Aaf && m.desc.scene.hasGlossyMaterials; }

// Filter images (several MB) exist only once a filter method has been chosen.
void ensureFilters(Module& m) {
  if (!usesScreenFilters(m.settings.method)) return;
  if (!m.filters.set.set)
    m.filters = createScreenFilters(m.ctx, m.desc.width, m.desc.height,
                                    {m.guidance.view, m.position.view, m.noisyIndirect.view, m.indirect.view, m.debug.view,
                                     m.aafParams.view});
  if (aafSpecular(m) && !m.filters.aafGlossySets[0].set) {
    // The glossy terms are filtered in place: β in their alpha, the filter's temp image shared.
    engine::Image* terms[] = {&m.aafGlossy, &m.aafGlossyEdge};
    for (int i = 0; i < 2; ++i)
      m.filters.aafGlossySets[i] = createFilterSet(
          m.ctx, {m.guidance.view, m.position.view, terms[i]->view, terms[i]->view, m.debug.view, terms[i]->view});
  }
  if (m.settings.method == Method::Gif && !m.filters.a[0].image) ensureGuidedStack(m.ctx, m.filters);
}

uint32_t hashMode(Method method) {
  return method == Method::Nhpsf ? gpu::HG_MODE_NHPSF : method == Method::Anhpsf ? gpu::HG_MODE_ANHPSF : gpu::HG_MODE_HPSF;
}

// The hash map exists once a hash method is chosen, at the capacity the
// settings ask for, with two tables for strict eviction and a walk per pixel
// for anhpsf. Its programs are built for the modes used.
void ensureHashGrid(Module& m) {
  if (!usesHashGrid(m.settings.method)) return;
  uint32_t capacity = hashCapacity(m.settings.hpsf, m.desc.width, m.desc.height);
  uint32_t tables = m.settings.hpsf.eviction == EvictionPolicy::Strict ? 2 : 1;
  bool walks = m.settings.method == Method::Anhpsf;
  VkDescriptorSetLayout layouts[2] = {m.desc.scene.layout, m.frameSet.layout};
  if (m.hash.capacity == capacity && m.hash.tables == tables && (m.hash.walkPixels > 0) == walks) {
    ensureHashGridPrograms(m.ctx, m.hash, layouts, sceneSpecialization(m), hashMode(m.settings.method),
                           m.desc.scene.traversal);
    return;
  }
  if (m.hash.capacity) destroyHashGrid(m.ctx, m.hash);  // a new map starts empty (the caller let the last frame finish)
  m.hash = createHashGrid(m.ctx, capacity, tables, m.desc.width, m.desc.height, kFramesInFlight, walks);
  ensureHashGridPrograms(m.ctx, m.hash, layouts, sceneSpecialization(m), hashMode(m.settings.method),
                           m.desc.scene.traversal);
}

// Each method's programs are compiled when it is first chosen: a module that
// only ever runs one method compiles only that method's shaders.
void ensurePrograms(Module& m) {
  const Settings& s = m.settings;
  VkDescriptorSetLayout layouts[] = {m.desc.scene.layout, m.frameSet.layout};
  const glm::uvec2 tile{GI_GROUP_SIZE, GI_GROUP_SIZE};
  auto spec = sceneSpecialization(m);
  auto make = [&](engine::ComputeProgram& p, std::span<const uint32_t> spirv, uint32_t push) {
    if (!p.pipeline) p = engine::createComputeProgram(m.ctx, spirv, layouts, push, tile, spec);
  };
  bool pathsFromGBuffer = !usesHashGrid(s.method) && !isAaf(s.method);
  if (pathsFromGBuffer) make(m.rawTrace, GI_SCENE_SPIRV(m.desc.scene.traversal, gi_raw_trace_comp), sizeof(gpu::GiRawPush));
  if (usesScreenFilters(s.method)) make(m.guidancePass, GI_SCENE_SPIRV(m.desc.scene.traversal, gi_guidance_comp), 0);
  if (s.method == Method::Gif && s.gif.supersamples > 0)
    make(m.supersample, GI_SCENE_SPIRV(m.desc.scene.traversal, gi_supersample_comp), sizeof(gpu::GiSupersamplePush));
  if (isAaf(s.method)) {
    make(m.aafSample, GI_SCENE_SPIRV(m.desc.scene.traversal, aaf_sample_comp), sizeof(gpu::AafPush));
    make(m.aafAdaptive, GI_SCENE_SPIRV(m.desc.scene.traversal, aaf_adaptive_comp), sizeof(gpu::AafPush));
  }
}

float cosDegrees(float degrees) { return std::cos(degrees * 3.14159265f / 180.0f); }

// World size of a pixel per metre of view depth.
float pixelScale(const gpu::GpuCamera& c) { return 2.0f * c.tanHalfFovY / c.imageSize.y; }

// The counters a frame slot copied back (valid once that frame has completed).
gpu::GiCounters slotCounters(const Module& m, uint32_t slot) {
  gpu::GiCounters c;
  std::memcpy(&c, static_cast<const std::byte*>(m.counters.mapped) + sizeof(gpu::GiCounters) * (1 + slot), sizeof(c));
  return c;
}

// The ray budget: paths per pixel such that pixels × spp × (rays per path, as
// measured on the previous frame) stays within settings.rayBudget.
uint32_t samplesWithinBudget(const Module& m, uint32_t requested, uint32_t frameIndex) {
  if (m.settings.rayBudget == 0 || frameIndex == 0) return requested;
  uint32_t previous = (frameIndex - 1) % kFramesInFlight;
  if (!m.slotRecorded[previous] || m.slotSpp[previous] == 0) return requested;
  gpu::GiCounters c = slotCounters(m, previous);
  double paths = double(m.desc.width) * m.desc.height * m.slotSpp[previous];
  double raysPerPath = c.raysTraced > 0 ? double(c.raysTraced) / paths : 1.0;
  double affordable = double(m.settings.rayBudget) / (double(m.desc.width) * m.desc.height * raysPerPath);
  return uint32_t(std::clamp(affordable, 1.0, double(requested)));
}

// AAF's budget in samples: rayBudget over the rays per sample measured last frame.
uint32_t aafSampleBudget(const Module& m, uint32_t frameIndex) {
  if (m.settings.rayBudget == 0 || frameIndex == 0) return 0;
  uint32_t previous = (frameIndex - 1) % kFramesInFlight;
  if (!m.slotRecorded[previous]) return 0;
  gpu::GiCounters c = slotCounters(m, previous);
  double raysPerSample = c.tracedSamples > 0 ? double(c.raysTraced) / double(c.tracedSamples) : 4.0;
  double budget = double(m.settings.rayBudget) / raysPerSample;
  return uint32_t(std::clamp(budget, 1.0, 4.0e9));
}

// Everything whose size follows the render size: the module's images (bound
// in the frame set), the filters' images and the hash map (its default
// capacity and the walks are per pixel). Created at create() and resize().
void createSizedResources(Module& m) {
  for (size_t i = 0; engine::Image* img = ownedImages(m, i); ++i) {
    bool unused = (img == &m.aafGlossy || img == &m.aafGlossyEdge) && !m.desc.scene.hasGlossyMaterials;
    *img = outputImage(m, unused ? VkExtent2D{1, 1} : VkExtent2D{m.desc.width, m.desc.height});
  }
  engine::DescriptorWriter(m.frameSet.set)
      .storageImage(gpu::GI_BINDING_OUT_DIRECT, m.direct.view)
      .storageImage(gpu::GI_BINDING_OUT_INDIRECT, m.indirect.view)
      .storageImage(gpu::GI_BINDING_OUT_COMPOSITE, m.composite.view)
      .storageImage(gpu::GI_BINDING_HISTORY_DIRECT, m.historyDirect.view)
      .storageImage(gpu::GI_BINDING_HISTORY_INDIRECT, m.historyIndirect.view)
      .storageImage(gpu::GI_BINDING_NOISY_INDIRECT, m.noisyIndirect.view)
      .storageImage(gpu::GI_BINDING_GUIDANCE, m.guidance.view)
      .storageImage(gpu::GI_BINDING_POSITION, m.position.view)
      .storageImage(gpu::GI_BINDING_DEBUG, m.debug.view)
      .storageImage(gpu::GI_BINDING_AAF_PARAMS, m.aafParams.view)
      .storageImage(gpu::GI_BINDING_AAF_SUM, m.aafSum.view)
      .storageImage(gpu::GI_BINDING_AAF_GLOSSY, m.aafGlossy.view)
      .storageImage(gpu::GI_BINDING_AAF_GLOSSY_EDGE, m.aafGlossyEdge.view)
      .write(m.ctx);
  m.imagesInitialised = false;
  m.boundGBuffer = {};  // the caller's G-buffer is re-bound on the next frame
  m.historyLength = 0;
  ensureFilters(m);
  ensureHashGrid(m);
}

void destroySizedResources(Module& m) {
  if (m.filters.set.set) destroyScreenFilters(m.ctx, m.filters);
  if (m.hash.capacity) destroyHashGrid(m.ctx, m.hash);
  for (size_t i = 0; engine::Image* img = ownedImages(m, i); ++i) engine::destroyImage(m.ctx, *img);
}

// Device memory the module holds now.
uint64_t memoryBytes(Module& m) {
  uint64_t bytes = m.frameConstants.size + m.counters.size + m.filters.memoryBytes + m.hash.memoryBytes;
  for (size_t i = 0; const engine::Image* img = ownedImages(m, i); ++i) bytes += img->allocationSize;
  return bytes;
}

}  // namespace

void computeToComputeBarrier(VkCommandBuffer cmd) {
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

// One pass of the frame script: label and timestamps around a dispatch and
// the barrier that publishes its writes to the next compute pass.
void runPass(Module& m, VkCommandBuffer cmd, uint32_t slot, const char* name, const engine::ComputeProgram& program,
             std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* push, uint32_t pushSize) {
  beginPass(m, cmd, slot, name);
  engine::dispatch(cmd, program, sets, threads, push, pushSize);
  computeToComputeBarrier(cmd);
  endPass(m, cmd, slot);
}

template <typename Push>
void runPassWith(Module& m, VkCommandBuffer cmd, uint32_t slot, const char* name, const engine::ComputeProgram& program,
                 std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const Push& push) {
  runPass(m, cmd, slot, name, program, sets, threads, &push, sizeof(Push));
}

PassHooks passHooks(Module& m, uint32_t slot) {
  return {[&m, slot](VkCommandBuffer cmd, const char* name) { beginPass(m, cmd, slot, name); },
          [&m, slot](VkCommandBuffer cmd) { endPass(m, cmd, slot); }};
}

// The passes whose work is tracing paths (their time is what FrameStats'
// rays are traced in; the hash resolve's probe rays are a small part of it).
constexpr std::string_view kTracingPasses[] = {"raw_trace",   "aaf_sample",   "aaf_adaptive",   "hpsf_insert",
                                               "nhpsf_paths", "anhpsf_paths", "gif_supersample"};

bool tracesRays(std::string_view pass) {
  return std::find(std::begin(kTracingPasses), std::end(kTracingPasses), pass) != std::end(kTracingPasses);
}

void beginPass(Module& m, VkCommandBuffer cmd, uint32_t slot, const char* name) {
  uint32_t index = uint32_t(m.passNames[slot].size());
  m.passNames[slot].emplace_back(name);
  if (m.desc.debugLabels) {
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    vkCmdBeginDebugUtilsLabelEXT(cmd, &label);
  }
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, m.timestamps, (slot * kMaxPasses + index) * 2);
  engine::timestampFence(cmd);
}

void endPass(Module& m, VkCommandBuffer cmd, uint32_t slot) {
  uint32_t index = uint32_t(m.passNames[slot].size()) - 1;
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, m.timestamps, (slot * kMaxPasses + index) * 2 + 1);
  if (m.desc.debugLabels) vkCmdEndDebugUtilsLabelEXT(cmd);
}

uint32_t version() { return GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR; }

Error create(const ModuleDesc& desc, const Settings& settings, Module*& out) {
  out = nullptr;
  if (Error e = checkDesc(desc)) return e;
  if (Error e = validate(settings)) return e;
  // The module shares the engine's volk loader; load it for this device if the host has not.
  if (volkGetLoadedDevice() != desc.device) {
    if (volkInitialize() != VK_SUCCESS) return {ErrorCode::MissingHandle, "no Vulkan loader found"};
    volkLoadInstanceOnly(desc.instance);
    volkLoadDevice(desc.device);
  }
  if (Error e = checkFeatures(desc)) return e;
  Module* m = new Module;
  m->desc = desc;
  m->settings = settings;
  m->ctx.instance = desc.instance;
  m->ctx.physicalDevice = desc.physicalDevice;
  m->ctx.device = desc.device;
  vkGetPhysicalDeviceProperties(desc.physicalDevice, &m->ctx.properties);
  vkGetPhysicalDeviceMemoryProperties(desc.physicalDevice, &m->ctx.memoryProperties);

  m->frameConstants = engine::createBuffer(m->ctx, sizeof(gpu::GiFrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                           engine::MemoryKind::HostVisible);
  m->counters = engine::createBuffer(m->ctx, sizeof(gpu::GiCounters) * (1 + kFramesInFlight),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                         VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                     engine::MemoryKind::HostVisible);
  std::memset(m->counters.mapped, 0, m->counters.size);

  m->frameSet = engine::createDescriptorSet(m->ctx, kFrameBindings);
  // The shaders' live counter is the first GiCounters; the others are per-slot copies for readback.
  engine::DescriptorWriter(m->frameSet.set)
      .buffer(gpu::GI_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, m->frameConstants.buffer)
      .buffer(gpu::GI_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m->counters.buffer)
      .write(m->ctx);
  VkDescriptorSetLayout layouts[] = {desc.scene.layout, m->frameSet.layout};
  m->composite_ = engine::createComputeProgram(m->ctx, GI_SCENE_SPIRV(desc.scene.traversal, gi_composite_comp), layouts, sizeof(gpu::GiCompositePush),
                                               {GI_GROUP_SIZE, GI_GROUP_SIZE}, sceneSpecialization(*m));
  createSizedResources(*m);
  ensurePrograms(*m);

  VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  q.queryType = VK_QUERY_TYPE_TIMESTAMP;
  q.queryCount = 2 * kMaxPasses * kFramesInFlight;
  VK_CHECK(vkCreateQueryPool(desc.device, &q, nullptr, &m->timestamps));
  out = m;
  return {};
}

void destroy(Module* m) {
  if (!m) return;
  vkDestroyQueryPool(m->ctx.device, m->timestamps, nullptr);
  for (engine::ComputeProgram* p : {&m->rawTrace, &m->composite_, &m->guidancePass, &m->supersample, &m->aafSample, &m->aafAdaptive})
    engine::destroyComputeProgram(m->ctx, *p);
  destroySizedResources(*m);
  engine::destroyDescriptorSet(m->ctx, m->frameSet);
  engine::destroyBuffer(m->ctx, m->frameConstants);
  engine::destroyBuffer(m->ctx, m->counters);
  delete m;
}

Error setSettings(Module* m, const Settings& settings) {
  if (Error e = validate(settings)) return e;
  m->settings = settings;
  m->historyLength = 0;  // any change invalidates accumulated frames
  ensurePrograms(*m);
  ensureFilters(*m);
  ensureHashGrid(*m);
  return {};
}

Error resize(Module* m, uint32_t width, uint32_t height) {
  ModuleDesc desc = m->desc;
  desc.width = width;
  desc.height = height;
  if (Error e = checkDesc(desc)) return e;
  if (width == m->desc.width && height == m->desc.height) return {};
  destroySizedResources(*m);
  m->desc = desc;
  createSizedResources(*m);
  return {};
}

void invalidate(Module* m, Invalidate what) {
  m->historyLength = 0;
  if (what == Invalidate::All) m->hash.cleared = false;  // re-zeroed at the start of the next frame
  else m->hash.forgetLight = true;  // geometry stands: cells, probes and continued paths stay, their light goes
}

Outputs outputs(const Module* m) {
  return {m->direct.image, m->indirect.image, m->composite.image, m->direct.view, m->indirect.view, m->composite.view};
}

void recordFrame(Module* m, VkCommandBuffer cmd, const FrameInputs& in) {
  const uint32_t slot = in.frameIndex % kFramesInFlight;
  const Settings& s = m->settings;
  gpu::GiFrameConstants frame{in.camera, in.previousCamera, {m->desc.width, m->desc.height}, in.frameIndex,
                              std::max(m->desc.scene.extent, 1e-6f)};
  std::memcpy(m->frameConstants.mapped, &frame, sizeof(frame));
  if (!sameView(in.gbuffer, m->boundGBuffer)) {
    engine::DescriptorWriter(m->frameSet.set)
        .storageImage(gpu::GI_BINDING_GB_NORMAL, in.gbuffer.normal)
        .storageImage(gpu::GI_BINDING_GB_ALBEDO, in.gbuffer.albedo)
        .storageImage(gpu::GI_BINDING_GB_MATERIAL, in.gbuffer.material)
        .storageImage(gpu::GI_BINDING_GB_EMISSION, in.gbuffer.emission)
        .storageImage(gpu::GI_BINDING_GB_MOTION, in.gbuffer.motion)
        .storageImage(gpu::GI_BINDING_GB_VIEWZ, in.gbuffer.viewZ)
        .write(m->ctx);
    m->boundGBuffer = in.gbuffer;
  }
  if (!m->imagesInitialised) {
    for (size_t i = 0; engine::Image* img = ownedImages(*m, i); ++i)
      engine::imageBarrier(cmd, img->image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE,
                           0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    m->imagesInitialised = true;
  }
  // History survives only while the view and the settings stay put.
  bool accumulate = s.method == Method::Raw && s.raw.temporalAccumulation;
  if (!accumulate || !sameCamera(in.camera, m->historyCamera)) m->historyLength = 0;
  m->historyCamera = in.camera;

  vkCmdResetQueryPool(cmd, m->timestamps, slot * kMaxPasses * 2, kMaxPasses * 2);
  m->passNames[slot].clear();
  vkCmdFillBuffer(cmd, m->counters.buffer, 0, sizeof(gpu::GiCounters), 0);
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  VkDescriptorSet sets[] = {m->desc.scene.set, m->frameSet.set};
  const glm::uvec2 size{m->desc.width, m->desc.height};

  uint32_t spp = 0;
  if (isAaf(s.method)) {
    // Passes: 16 stratified rays give reflector distances, β and n per pixel; then the remaining n − 16.
    gpu::AafPush aaf{s.aaf.mu, s.aaf.alpha, m->desc.scene.extent, s.seed, s.method == Method::AafAo ? 1u : 0u,
                     aafSampleBudget(*m, in.frameIndex), s.maxBounces, s.russianRouletteStart, s.aaf.uniformSamples,
                     aafSpecular(*m) ? 1u : 0u, 0, 0};
    runPassWith(*m, cmd, slot, "aaf_sample", m->aafSample, sets, size, aaf);
    runPassWith(*m, cmd, slot, "aaf_adaptive", m->aafAdaptive, sets, size, aaf);
  } else if (usesHashGrid(s.method)) {
    spp = samplesWithinBudget(*m, tracedSamplesPerPixel(s), in.frameIndex);
    const HpsfSettings& h = s.hpsf;
    bool strict = h.eviction == EvictionPolicy::Strict;
    gpu::HgPush push{m->hash.capacity, h.probeWindow, h.filterWidth, pixelScale(in.camera), h.jitter, h.normalBits,
                     h.stochasticLod ? 1u : 0u, h.clampSigma, in.frameIndex, h.historyFrames, h.staleFrames, h.minSamples,
                     s.seed, spp, s.maxBounces, s.russianRouletteStart, hashTableBase(m->hash, in.frameIndex),
                     previousHashTableBase(m->hash, in.frameIndex), strict ? 1u : 0u, uint32_t(s.debugView),
                     hashMode(s.method), s.method == Method::Nhpsf ? h.pathDepth : h.continuationDepth,
                     h.secondaryWidthScale, strict ? 0u : h.validationInterval, radianceScale(*m),
                     m->hash.forgetLight ? 1u : 0u, h.normalJitter, uint32_t(h.secondaryLod),
                     s.method == Method::Hpsf ? 0u : h.historySamples, 0, 0, 0};
    m->hash.forgetLight = false;
    VkDescriptorSet hashSets[] = {m->desc.scene.set, m->frameSet.set, m->hash.set.set};
    recordHashGridFrameStart(cmd, m->hash, in.frameIndex);
    if (s.method == Method::Hpsf) {
      // Pass: paths from the G-buffer; their indirect radiance goes into the filter vertex's cell.
      runPassWith(*m, cmd, slot, "hpsf_insert", m->hash.insert, hashSets, size, push);
    } else {
      // Pass: path segments from the G-buffer (nhpsf: pathDepth of them; anhpsf: the primary one and
      // one of each pixel's continued path); each diffuse vertex's cell gets what its segment brings.
      runPassWith(*m, cmd, slot, s.method == Method::Nhpsf ? "nhpsf_paths" : "anhpsf_paths", m->hash.paths, hashSets,
                  size, push);
    }
    // Pass: fold the frame's sums into each cell's history; evict stale cells.
    runPassWith(*m, cmd, slot, "hpsf_resolve", m->hash.resolve, hashSets, {m->hash.capacity, 1}, push);
    // Pass: each pixel reads its cell (or keeps its own sample).
    runPassWith(*m, cmd, slot, "hpsf_lookup", m->hash.lookup, hashSets, size, push);
    recordHashGridTelemetryCopy(cmd, m->hash, slot);
  } else {
    spp = samplesWithinBudget(*m, tracedSamplesPerPixel(s), in.frameIndex);
    // Pass: trace paths from the G-buffer (direct + demodulated indirect, optional temporal mean).
    gpu::GiRawPush raw{s.seed, spp, s.maxBounces, s.russianRouletteStart,
                       m->historyLength, s.raw.maxAccumulatedFrames, accumulate ? 1u : 0u, 0};
    runPassWith(*m, cmd, slot, "raw_trace", m->rawTrace, sets, size, raw);
  }

  if (usesScreenFilters(s.method)) {
    // Pass: the filters' guidance (normal, scaled depth) and world positions from the G-buffer.
    runPass(*m, cmd, slot, "guidance", m->guidancePass, sets, size, nullptr, 0);
    // Passes: the chosen filter, noisy indirect → indirect.
    PassHooks hooks = passHooks(*m, slot);
    if (s.method == Method::Sspsf) {
      const SspsfSettings& ss = s.sspsf;
      recordSspsf(cmd, m->filters,
                  {ss.window, ss.filterWidth, pixelScale(in.camera), cosDegrees(ss.normalLimitDegrees)},
                  hooks);
    } else if (isAaf(s.method)) {
      float cosLimit = cosDegrees(s.aaf.normalLimitDegrees);
      const uint32_t maxRadius = s.aaf.maxRadius;
      recordAafFilter(cmd, m->filters, m->filters.set.set, "diffuse", cosLimit, pixelScale(in.camera), maxRadius, hooks);
      if (aafSpecular(*m)) {  // glossy receivers: their specular terms, with the glossy β
        recordAafFilter(cmd, m->filters, m->filters.aafGlossySets[0].set, "glossy", cosLimit, pixelScale(in.camera),
                        maxRadius, hooks);
        recordAafFilter(cmd, m->filters, m->filters.aafGlossySets[1].set, "glossy_edge", cosLimit, pixelScale(in.camera),
                        maxRadius, hooks);
      }
    } else if (s.method == Method::Gif) {
      GuidedFilterParams gif{s.gif.radius, s.gif.epsilonNormal, s.gif.epsilonDepth, s.gif.guidanceDimensions,
                             s.debugView == DebugView::GifCoefficients};
      recordGuidedFilter(cmd, m->filters, gif, hooks);
    } else if (s.method == Method::Bilateral) {
      const BilateralSettings& b = s.bilateral;
      recordBilateral(cmd, m->filters, {b.radius, b.sigmaSpatial, b.sigmaNormal, b.sigmaDepth}, hooks);
    } else {
      const AtrousSettings& a = s.atrous;
      recordAtrous(cmd, m->filters, a.iterations, a.sigmaColor, a.sigmaNormal, a.sigmaPosition, hooks);
    }
  }

  // Pass: composite (or the chosen debug view).
  gpu::GiCompositePush composite{uint32_t(s.debugView), s.method == Method::AafAo ? 1u : 0u, m->desc.scene.extent,
                                 pixelScale(in.camera), aafSpecular(*m) ? 1u : 0u, 0, 0, 0};
  runPassWith(*m, cmd, slot, "composite", m->composite_, sets, size, composite);

  if (s.method == Method::Gif && s.gif.supersamples > 0 && s.debugView == DebugView::None) {
    // Pass: extra eye rays with their own direct light and geometry-aware indirect lookup.
    runPassWith(*m, cmd, slot, "gif_supersample", m->supersample, sets, size, gpu::GiSupersamplePush{s.seed, s.gif.supersamples});
  }
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);

  // Counters to this slot's readback copy.
  VkBufferCopy copy{0, sizeof(gpu::GiCounters) * (1 + slot), sizeof(gpu::GiCounters)};
  vkCmdCopyBuffer(cmd, m->counters.buffer, m->counters.buffer, 1, &copy);

  if (accumulate) m->historyLength = std::min(m->historyLength + 1, s.raw.maxAccumulatedFrames);
  m->slotFrameIndex[slot] = in.frameIndex;
  m->slotHistory[slot] = m->historyLength;
  m->slotSpp[slot] = spp;
  m->slotMethod[slot] = s.method;
  m->slotRecorded[slot] = true;
}

FrameStats stats(Module* m) {
  // Newest recorded slot first; a slot whose timestamps are not ready is still in flight.
  uint32_t order[kFramesInFlight] = {0, 1};
  if (m->slotFrameIndex[1] > m->slotFrameIndex[0]) std::swap(order[0], order[1]);
  for (uint32_t slot : order) {
    if (!m->slotRecorded[slot] || m->passNames[slot].empty()) continue;
    uint32_t n = uint32_t(m->passNames[slot].size());
    std::vector<uint64_t> ticks(2 * n);
    VkResult r = vkGetQueryPoolResults(m->ctx.device, m->timestamps, slot * kMaxPasses * 2, 2 * n, ticks.size() * 8,
                                       ticks.data(), 8, VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) continue;
    FrameStats st;
    st.frameIndex = m->slotFrameIndex[slot];
    for (uint32_t i = 0; i < n; ++i) {
      double ms = double(ticks[2 * i + 1] - ticks[2 * i]) * m->ctx.properties.limits.timestampPeriod * 1e-6;
      st.passes.push_back({m->passNames[slot][i], ms, tracesRays(m->passNames[slot][i])});
      st.totalMs += ms;
    }
    gpu::GiCounters c = slotCounters(*m, slot);
    st.raysTraced = c.raysTraced;
    st.sanitized = c.sanitized;
    st.accumulatedFrames = m->slotHistory[slot];
    st.samplesPerPixel = m->slotSpp[slot];
    uint32_t pixels = m->desc.width * m->desc.height;
    if (c.tracedSamples > 0 && pixels > 0) st.samplesPerPixel = (c.tracedSamples + pixels / 2) / pixels;  // AAF: mean
    st.memoryBytes = memoryBytes(*m);
    if (usesHashGrid(m->slotMethod[slot]) && m->hash.capacity) {
      gpu::HgTelemetry t = readHashGridTelemetry(m->hash, slot);
      st.hash.capacity = m->hash.capacity;
      st.hash.occupied = t.occupied;
      st.hash.inserts = t.inserts;
      st.hash.failedInserts = t.failedInserts;
      st.hash.meanProbe = t.inserts ? float(t.probeSum) / float(t.inserts) : 0.0f;
      st.hash.maxProbe = t.probeMax;
      st.hash.evicted = t.evicted;
      st.hash.overflows = t.overflows;
      st.hash.staleResets = t.staleResets;
      st.hash.transported = double(t.transported) / HG_FIXED_POINT_SCALE / radianceScale(*m);
      st.hash.meanContinuationDepth = t.continued ? float(t.depthSum) / float(t.continued) : 0.0f;
      st.hash.reads = t.reads;
      st.hash.readMisses = t.readMisses;
    }
    m->lastStats = st;
    break;
  }
  return m->lastStats;
}

}  // namespace gi
