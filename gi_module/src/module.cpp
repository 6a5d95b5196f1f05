// Module lifetime: create, settings, resize, invalidate, destroy. Everything
// a call replaces is retired, never destroyed under a frame in flight; a call
// that fails leaves the module as it was.
#include "module.h"

#include "programs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "gi/vk/names.h"
#include "shared/aaf.h"

namespace gi {
namespace {

std::string sizeText(uint32_t w, uint32_t h) { return std::to_string(w) + "×" + std::to_string(h); }

Error checkSize(const char* what, uint32_t w, uint32_t h) {
  if (w == 0 || h == 0) return {ErrorCode::ZeroSize, std::string(what) + " = " + sizeText(w, h) + " has a zero side"};
  if (w > 16384 || h > 16384)
    return {ErrorCode::SizeTooLarge, std::string(what) + " = " + sizeText(w, h) + " exceeds 16384 per side"};
  return {};
}

// `what`: how the caller names the SceneDesc ("desc.scene", "gi::setScene scene").
Error checkScene(const SceneDesc& scene, const std::string& what) {
  if (!scene.layout || !scene.set) return {ErrorCode::MissingHandle, what + ".layout and " + what + ".set must be set"};
  if (!(scene.typicalRadiance > 0.0f) || !std::isfinite(scene.typicalRadiance))
    return {ErrorCode::OutOfRange, what + ".typicalRadiance = " + std::to_string(scene.typicalRadiance) +
                                       " is not a positive finite radiance"};
  if (scene.traversal != Traversal::RayQuery && scene.traversal != Traversal::Compute)
    return {ErrorCode::OutOfRange, what + ".traversal = " + std::to_string(uint32_t(scene.traversal)) +
                                       " is neither Traversal::RayQuery nor Traversal::Compute"};
  if (scene.traversal == Traversal::Compute && !scene.hasComputeBvh)
    return {ErrorCode::OutOfRange, what +
                                       ".traversal = Traversal::Compute, but the scene was built for ray queries "
                                       "alone (gi::SceneCreateDesc::bothTraversals builds the compute BVH too)"};
  return {};
}

// The G-buffer formats each encoding accepts (gi.h lists them).
struct AcceptedFormats {
  uint32_t encoding;
  std::span<const VkFormat> formats;
};
constexpr VkFormat kHardwareDepthFormats[] = {VK_FORMAT_D32_SFLOAT, VK_FORMAT_D32_SFLOAT_S8_UINT,
                                              VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_X8_D24_UNORM_PACK32,
                                              VK_FORMAT_D16_UNORM};
constexpr VkFormat kLinearDepthFormats[] = {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R16_SFLOAT};
constexpr VkFormat kXyzNormalFormats[] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
                                          VK_FORMAT_R16G16B16A16_SNORM, VK_FORMAT_R8G8B8A8_SNORM};
constexpr VkFormat kXyzUnormNormalFormats[] = {VK_FORMAT_A2B10G10R10_UNORM_PACK32, VK_FORMAT_A2R10G10B10_UNORM_PACK32,
                                               VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R16G16B16A16_UNORM};
constexpr VkFormat kOctahedralFormats[] = {VK_FORMAT_R16G16_UNORM, VK_FORMAT_R8G8_UNORM};
constexpr VkFormat kOctahedralSignedFormats[] = {VK_FORMAT_R16G16_SNORM, VK_FORMAT_R16G16_SFLOAT,
                                                 VK_FORMAT_R32G32_SFLOAT};
const AcceptedFormats kNormalFormats[] = {
    {uint32_t(NormalEncoding::Xyz), kXyzNormalFormats},
    {uint32_t(NormalEncoding::XyzUnorm), kXyzUnormNormalFormats},
    {uint32_t(NormalEncoding::Octahedral), kOctahedralFormats},
    {uint32_t(NormalEncoding::OctahedralSigned), kOctahedralSignedFormats},
};
const AcceptedFormats kDepthFormats[] = {
    {uint32_t(DepthEncoding::LinearViewZ), kLinearDepthFormats},
    {uint32_t(DepthEncoding::Hardware), kHardwareDepthFormats},
    {uint32_t(DepthEncoding::HardwareReversed), kHardwareDepthFormats},
};
const VkFormat kAlbedoFormats[] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_UNORM,
                                   VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R16G16B16A16_SFLOAT};
const VkImageLayout kDepthLayouts[] = {VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                                       VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};

template <typename T, size_t N>
bool contains(const T (&list)[N], T value) {
  return std::find(std::begin(list), std::end(list), value) != std::end(list);
}

// The encodings' names, as gi.h spells them (in their enums' order).
constexpr const char* kNormalEncodingNames[] = {"NormalEncoding::Xyz", "NormalEncoding::XyzUnorm",
                                                "NormalEncoding::Octahedral", "NormalEncoding::OctahedralSigned"};
constexpr const char* kDepthEncodingNames[] = {"DepthEncoding::LinearViewZ", "DepthEncoding::Hardware",
                                               "DepthEncoding::HardwareReversed"};

static_assert(std::size(kNormalEncodingNames) == std::size(kNormalFormats) &&
                  std::size(kDepthEncodingNames) == std::size(kDepthFormats),
              "a name for every encoding");

std::string formatList(std::span<const VkFormat> formats) {
  std::string list;
  for (VkFormat f : formats) list += (list.empty() ? "" : ", ") + vk::formatName(f);
  return list;
}

// `encoding` valid and `format` one it accepts; the errors name the format, the encoding and what it accepts.
Error checkEncoding(std::span<const AcceptedFormats> table, std::span<const char* const> names, uint32_t encoding,
                    VkFormat format, const char* encodingField, const char* formatField) {
  for (const AcceptedFormats& a : table)
    if (a.encoding == encoding) {
      if (std::find(a.formats.begin(), a.formats.end(), format) != a.formats.end()) return {};
      return {ErrorCode::UnsupportedFormat, std::string(formatField) + " = " + vk::formatName(format) + " is not one " +
                                                encodingField + " = " + names[encoding] +
                                                " accepts: " + formatList(a.formats)};
    }
  return {ErrorCode::OutOfRange, std::string(encodingField) + " = " + std::to_string(encoding) + " is not one of " +
                                     std::to_string(names.size()) + " encodings (" + names[0] + " …)"};
}

Error checkGBuffer(const GBufferDesc& g) {
  if (Error e = checkEncoding(kNormalFormats, kNormalEncodingNames, uint32_t(g.normalEncoding), g.normalFormat,
                              "desc.gbuffer.normalEncoding", "desc.gbuffer.normalFormat"))
    return e;
  if (Error e = checkEncoding(kDepthFormats, kDepthEncodingNames, uint32_t(g.depthEncoding), g.depthFormat,
                              "desc.gbuffer.depthEncoding", "desc.gbuffer.depthFormat"))
    return e;
  if (!contains(kAlbedoFormats, g.albedoFormat))
    return {ErrorCode::UnsupportedFormat, "desc.gbuffer.albedoFormat = " + vk::formatName(g.albedoFormat) +
                                              " is not one the module reads: " + formatList(kAlbedoFormats)};
  if (g.colorLayout != VK_IMAGE_LAYOUT_GENERAL && g.colorLayout != VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
    return {ErrorCode::OutOfRange, "desc.gbuffer.colorLayout = " + vk::layoutName(g.colorLayout) +
                                       " is not GENERAL or SHADER_READ_ONLY_OPTIMAL"};
  if (!contains(kDepthLayouts, g.depthLayout))
    return {ErrorCode::OutOfRange, "desc.gbuffer.depthLayout = " + vk::layoutName(g.depthLayout) +
                                       " is not GENERAL or a read-only depth or shader layout"};
  if (uint32_t(g.motion) > uint32_t(MotionUnits::Ndc))
    return {ErrorCode::OutOfRange,
            "desc.gbuffer.motion = " + std::to_string(uint32_t(g.motion)) + " is not a MotionUnits (Pixels, Uv, Ndc)"};
  for (int k = 0; k < 2; ++k)
    if (!std::isfinite(g.motionScale[k]) || g.motionScale[k] == 0.0f)
      return {ErrorCode::OutOfRange, "desc.gbuffer.motionScale[" + std::to_string(k) + "] = " +
                                         std::to_string(g.motionScale[k]) + " is not a finite, non-zero factor"};
  if (uint32_t(g.glossy) > uint32_t(GlossyFlag::FromMaterial))
    return {ErrorCode::OutOfRange, "desc.gbuffer.glossy = " + std::to_string(uint32_t(g.glossy)) +
                                       " is not a GlossyFlag (AlbedoAlpha, FromMaterial)"};
  return {};
}

// The device samples every G-buffer format the engine named.
Error checkGBufferFormats(const Module& m) {
  const GBufferDesc& g = m.desc.gbuffer;
  const std::pair<VkFormat, const char*> formats[] = {{g.normalFormat, "desc.gbuffer.normalFormat"},
                                                      {g.albedoFormat, "desc.gbuffer.albedoFormat"},
                                                      {g.depthFormat, "desc.gbuffer.depthFormat"}};
  for (const auto& [format, field] : formats) {
    VkFormatProperties p{};
    m.gpu.fn.vkGetPhysicalDeviceFormatProperties(m.desc.physicalDevice, format, &p);
    if (!(p.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
      return {ErrorCode::UnsupportedFormat,
              std::string(field) + " = " + vk::formatName(format) + ": the device cannot sample it"};
  }
  return {};
}

// The outputs' formats (B10G11R11 is not every device's storage format).
Error checkOutputFormats(const Module& m) {
  const std::pair<const char*, VkFormat> outputs[] = {{"desc.outputFormat", m.desc.outputFormat},
                                                      {"desc.compositeFormat", compositeFormat(m.desc)}};
  for (const auto& [field, format] : outputs) {
    VkFormatProperties p{};
    m.gpu.fn.vkGetPhysicalDeviceFormatProperties(m.desc.physicalDevice, format, &p);
    if (!(p.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT))
      return {ErrorCode::UnsupportedFormat, std::string(field) + " = " + vk::formatName(format) +
                                                ": the device cannot store to it (a storage image)"};
  }
  return {};
}

Error checkDesc(const ModuleDesc& d) {
  if (d.structSize != sizeof(ModuleDesc))
    return {ErrorCode::VersionMismatch, "desc.structSize = " + std::to_string(d.structSize) +
                                            " is not this library's " + std::to_string(sizeof(ModuleDesc)) +
                                            ": built against another gi.h"};
  if (!d.getInstanceProcAddr)
    return {ErrorCode::MissingHandle, "desc.getInstanceProcAddr must be set (the engine's vkGetInstanceProcAddr)"};
  if (!d.instance || !d.physicalDevice || !d.device)
    return {ErrorCode::MissingHandle, "desc.instance, desc.physicalDevice and desc.device must be set"};
  if (Error e = checkScene(d.scene, "desc.scene")) return e;
  if (Error e = checkSize("desc.width × desc.height", d.width, d.height)) return e;
  if (d.maxWidth || d.maxHeight) {
    if (Error e = checkSize("desc.maxWidth × desc.maxHeight", d.maxWidth, d.maxHeight)) return e;
    if (d.width > d.maxWidth || d.height > d.maxHeight)
      return {ErrorCode::OutOfRange,
              "desc.width × desc.height = " + sizeText(d.width, d.height) +
                  " exceeds desc.maxWidth × desc.maxHeight = " + sizeText(d.maxWidth, d.maxHeight)};
  }
  if (d.framesInFlight < 1 || d.framesInFlight > kMaxFramesInFlight)
    return {ErrorCode::OutOfRange, "desc.framesInFlight = " + std::to_string(d.framesInFlight) + " is outside [1, " +
                                       std::to_string(kMaxFramesInFlight) + "]"};
  if (Error e = checkGBuffer(d.gbuffer)) return e;
  if (d.outputLayout != VK_IMAGE_LAYOUT_GENERAL && d.outputLayout != VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL &&
      d.outputLayout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
    return {ErrorCode::OutOfRange, "desc.outputLayout = " + vk::layoutName(d.outputLayout) +
                                       " is not GENERAL, SHADER_READ_ONLY_OPTIMAL or TRANSFER_SRC_OPTIMAL"};
  if (d.outputFormat != VK_FORMAT_R16G16B16A16_SFLOAT && d.outputFormat != VK_FORMAT_R32G32B32A32_SFLOAT &&
      d.outputFormat != VK_FORMAT_B10G11R11_UFLOAT_PACK32)
    return {ErrorCode::UnsupportedFormat, "desc.outputFormat = " + vk::formatName(d.outputFormat) +
                                              " is not R16G16B16A16Sfloat, R32G32B32A32Sfloat or "
                                              "B10G11R11UfloatPack32"};
  if (d.compositeFormat != VK_FORMAT_UNDEFINED && d.compositeFormat != VK_FORMAT_R16G16B16A16_SFLOAT &&
      d.compositeFormat != VK_FORMAT_R32G32B32A32_SFLOAT && d.compositeFormat != VK_FORMAT_B10G11R11_UFLOAT_PACK32)
    return {ErrorCode::UnsupportedFormat, "desc.compositeFormat = " + vk::formatName(d.compositeFormat) +
                                              " is not Undefined, R16G16B16A16Sfloat, R32G32B32A32Sfloat or "
                                              "B10G11R11UfloatPack32"};
  if (d.historyFormat != VK_FORMAT_R16G16B16A16_SFLOAT && d.historyFormat != VK_FORMAT_R32G32B32A32_SFLOAT)
    return {ErrorCode::UnsupportedFormat, "desc.historyFormat = " + vk::formatName(d.historyFormat) +
                                              " is not R16G16B16A16Sfloat or R32G32B32A32Sfloat"};
  return checkDeviceMemory(d.deviceMemory, "desc.deviceMemory");
}

// The features of gi/device.h: in the chain the engine enabled, if it says
// which, else among what the device supports.
Error checkFeatures(const Module& m) {
  const ModuleDesc& d = m.desc;
  const bool rayQuery = d.scene.traversal == Traversal::RayQuery;
  const char* missing = nullptr;
  const char* where = "the enabled features (desc.enabledFeatures)";
  if (d.enabledFeatures) {
    missing = firstMissingFeature(*d.enabledFeatures, rayQuery);
  } else {
    VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    as.pNext = &rq;
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.pNext = rayQuery ? &as : nullptr;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.pNext = &f13;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &f12;
    m.gpu.fn.vkGetPhysicalDeviceFeatures2(d.physicalDevice, &f2);
    missing = firstMissingFeature(f2, rayQuery);
    where = "the device";
  }
  if (!missing) {
    VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &p11;
    m.gpu.fn.vkGetPhysicalDeviceProperties2(d.physicalDevice, &p2);
    missing = firstMissingSubgroupSupport(p11.subgroupSupportedStages, p11.subgroupSupportedOperations);
    where = "the device";
  }
  if (!missing) return {};
  return {ErrorCode::MissingFeature, std::string(where) + " lacks " + missing + ", which the GI module needs" +
                                         (rayQuery ? " (with ray-query traversal)" : "") + "; see gi/device.h"};
}

// The hash map `s` needs for renders up to `width` × `height`.
struct HashGridShape {
  uint32_t capacity, tables;
  bool walks;
};
HashGridShape hashGridShape(const Settings& s, uint32_t width, uint32_t height) {
  return {hashCapacity(s, width, height), s.hpsf.eviction == EvictionPolicy::Strict ? 2u : 1u,
          s.method == Method::Anhpsf};
}

// Whether the hash map for `s` differs from the one the module holds.
bool hashGridChanges(const Module& m, const Settings& s) {
  if (!usesHashGrid(s.method)) return false;
  const HashGridShape want = hashGridShape(s, m.desc.maxWidth, m.desc.maxHeight);
  return !(m.hash.capacity == want.capacity && m.hash.tables == want.tables && (m.hash.walkPixels > 0) == want.walks);
}

vk::Status createHashGridFor(Module& m, const Settings& s, uint32_t width, uint32_t height, HashGrid& out) {
  const HashGridShape shape = hashGridShape(s, width, height);
  return createHashGrid(m.gpu, m.hashLayout, shape.capacity, shape.tables, width, height, m.desc.framesInFlight,
                        shape.walks, out);
}

// Host-visible buffers: frame constants (one per slot, each at the device's
// uniform offset alignment) and the counters (live + one copy per slot).
vk::Status createFrameBuffers(Module& m) {
  VkDeviceSize align = std::max<VkDeviceSize>(m.gpu.properties.limits.minUniformBufferOffsetAlignment, 16);
  m.frameConstantsStride = (sizeof(gpu::GiFrameConstants) + align - 1) / align * align;
  GI_TRY(vk::createBuffer(m.gpu, m.frameConstantsStride * m.desc.framesInFlight, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                          true, m.frameConstants));
  GI_TRY(vk::createBuffer(
      m.gpu, sizeof(gpu::GiCounters) * (1 + m.desc.framesInFlight),
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
      m.counters));
  if (m.counters.memory.mapped) std::memset(m.counters.memory.mapped, 0, m.counters.size);  // null: a prediction
  return {};
}

vk::Status createTimestamps(Module& m) {
  if (!m.desc.timestamps) return {};
  VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  q.queryType = VK_QUERY_TYPE_TIMESTAMP;
  q.queryCount = 2 * kMaxPasses * m.desc.framesInFlight;
  GI_VK(m.gpu.fn.vkCreateQueryPool(m.gpu.device, &q, m.gpu.allocator, &m.timestamps));
  return {};
}

// Every buffer and image the module holds at its size and settings, in the order predictMemory replays.
vk::Status createMemoryResources(Module& m) {
  GI_TRY(createFrameBuffers(m));
  GI_TRY(createOutputImages(m.gpu, m.desc.maxWidth, m.desc.maxHeight, m.desc, m.outputs));
  GI_TRY(createSizedResources(m, m.settings, m.desc.maxWidth, m.desc.maxHeight, m.outputs, m.sized));
  if (m.plan.hashGrid) GI_TRY(createHashGridFor(m, m.settings, m.desc.maxWidth, m.desc.maxHeight, m.hash));
  return {};
}

vk::Status createModuleResources(Module& m) {
  GI_TRY(vk::createDescriptorLayout(m.gpu, frameBindings(), m.frameLayout));
  GI_TRY(createHashGridLayout(m.gpu, m.hashLayout));
  GI_TRY(ensurePrograms(m, m.settings));
  GI_TRY(createMemoryResources(m));
  GI_TRY(createTimestamps(m));
  return {};
}

// Destroys everything; the GPU no longer uses the module.
void destroyModuleResources(Module& m) {
  releaseRetired(m, true);
  vk::Device& g = m.gpu;
  if (m.timestamps) g.fn.vkDestroyQueryPool(g.device, m.timestamps, g.allocator);
  m.timestamps = VK_NULL_HANDLE;
  destroySizedResources(g, m.sized);
  destroyOutputImages(g, m.outputs);
  destroyHashGrid(g, m.hash);
  destroyPrograms(m);
  vk::destroyBuffer(g, m.frameConstants);
  vk::destroyBuffer(g, m.counters);
  if (m.frameLayout) g.fn.vkDestroyDescriptorSetLayout(g.device, m.frameLayout, g.allocator);
  m.frameLayout = VK_NULL_HANDLE;
  vk::closeDevice(g);
}

// Retires `old` (frames in flight may read it) and keeps `next` in its place.
void replaceSized(Module& m, SizedResources& next) {
  auto old = std::make_shared<SizedResources>(std::move(m.sized));
  retire(m, [old](vk::Device& g) { destroySizedResources(g, *old); });
  m.sized = std::move(next);
}

void replaceHashGrid(Module& m, HashGrid& next) {
  if (m.hash.capacity) {
    auto old = std::make_shared<HashGrid>(std::move(m.hash));
    retire(m, [old](vk::Device& g) { destroyHashGrid(g, *old); });
  }
  m.hash = std::move(next);
}

}  // namespace

// gi.h: set 0's specialisation values for a scene.
std::array<uint32_t, SCENE_SPEC_COUNT> sceneSpecialization(const SceneDesc& scene) {
  return {scene.hasEmissiveTriangles ? 1u : 0u, scene.hasPunctualLights ? 1u : 0u, scene.hasAlphaMask ? 1u : 0u,
          scene.hasSky ? 1u : 0u};
}
// The scene's values, then the G-buffer's encodings (GI_SPEC_*): what every module program is specialised on.
std::array<uint32_t, GI_SPEC_COUNT> moduleSpecialization(const Module& m) {
  static_assert(SCENE_SPEC_COUNT == GI_SPEC_NORMAL_ENCODING, "the G-buffer's constants follow the scene's");
  const auto scene = sceneSpecialization(m.desc.scene);
  const GBufferDesc& g = m.desc.gbuffer;
  return {scene[0],
          scene[1],
          scene[2],
          scene[3],
          uint32_t(g.normalEncoding),
          uint32_t(g.depthEncoding),
          uint32_t(g.glossy),
          m.desc.checkBounds ? 1u : 0u,
          g.hasEmission ? 1u : 0u};
}

uint32_t hashMode(Method method) {
  return method == Method::Nhpsf    ? gpu::HG_MODE_NHPSF
         : method == Method::Anhpsf ? gpu::HG_MODE_ANHPSF
                                    : gpu::HG_MODE_HPSF;
}

Error vulkanError(const char* what, const vk::Status& status) {
  return {ErrorCode::VulkanCall,
          std::string(what) + ": " + (status.call ? status.call : "a Vulkan call") + " failed with " +
              resultName(status.result),
          status.result};
}

Error checkDeviceMemory(const DeviceMemoryCallbacks& c, const char* field) {
  if ((c.allocate == nullptr) != (c.free == nullptr))
    return {ErrorCode::MissingHandle, std::string(field) + (c.allocate ? ".free" : ".allocate") + " must be set with " +
                                          field + (c.allocate ? ".allocate" : ".free")};
  return {};
}

const char* resultName(VkResult result) {
  switch (result) {
#define GI_RESULT_CASE(r) \
  case r: return #r;
    GI_RESULT_CASE(VK_SUCCESS)
    GI_RESULT_CASE(VK_NOT_READY)
    GI_RESULT_CASE(VK_TIMEOUT)
    GI_RESULT_CASE(VK_INCOMPLETE)
    GI_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    GI_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    GI_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    GI_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    GI_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    GI_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    GI_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    GI_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    GI_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    GI_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    GI_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    GI_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    GI_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    GI_RESULT_CASE(VK_ERROR_INVALID_SHADER_NV)
    GI_RESULT_CASE(VK_ERROR_OUT_OF_DATE_KHR)
    GI_RESULT_CASE(VK_SUBOPTIMAL_KHR)
    GI_RESULT_CASE(VK_ERROR_SURFACE_LOST_KHR)
#undef GI_RESULT_CASE
    default: return "VkResult(unknown)";
  }
}

uint32_t version() { return GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR; }

// What create and predictMemory share: the desc and settings checked, the module's sizes and memory
// rules, its function table, and the output formats the device must store.
Error openModule(Module& m, const ModuleDesc& desc, const Settings& settings, const char* caller) {
  if (Error e = checkDesc(desc)) return e;
  if (Error e = validate(settings)) return e;
  m.desc = desc;
  m.desc.maxWidth = std::max(desc.maxWidth, desc.width);  // from here on: the largest size so far
  m.desc.maxHeight = std::max(desc.maxHeight, desc.height);
  m.settings = settings;
  m.plan = planMethod(m.desc.scene, settings);
  m.width = m.previousWidth = desc.width;
  m.height = m.previousHeight = desc.height;
  m.gpu.allocator = desc.allocationCallbacks;
  m.gpu.pipelineCache = desc.pipelineCache;
  m.gpu.memory.budget = desc.memoryBudgetBytes;
  m.gpu.memory.engine = desc.deviceMemory;
  if (vk::Status s = vk::openDevice(desc.getInstanceProcAddr, desc.instance, desc.physicalDevice, desc.device, m.gpu))
    return {ErrorCode::MissingHandle,
            std::string(caller) + ": desc.getInstanceProcAddr returned no " + s.call + " for this instance and device",
            s.result};
  return checkOutputFormats(m);
}

Error create(const ModuleDesc& desc, const Settings& settings, Module*& out) {
  out = nullptr;
  auto m = std::make_unique<Module>();
  if (Error e = openModule(*m, desc, settings, "gi::create")) return e;
  if (Error e = checkFeatures(*m); e || (e = checkGBufferFormats(*m))) return e;
  if (vk::Status s = createModuleResources(*m)) {
    Error e = vulkanError("gi::create", s);
    e.message += " (the module held " + std::to_string(m->gpu.memory.held) + " bytes of device memory)";
    destroyModuleResources(*m);
    return e;
  }
  out = m.release();
  return {};
}

Error predictMemory(const ModuleDesc& desc, const Settings& settings, MemoryPrediction& out) {
  out = {};
  Module m;  // what create would hold, on a simulated arena: the same rules, no allocation
  m.gpu.memory.simulate = true;
  if (Error e = openModule(m, desc, settings, "gi::predictMemory")) return e;
  const vk::Status built = createMemoryResources(m);
  if (!built)
    out = {m.gpu.memory.held, m.gpu.memory.used, m.sized.frameBytes, m.gpu.memory.used - m.sized.frameBytes,
           m.gpu.memory.allocations};
  destroyModuleResources(m);
  // Beyond memoryBudgetBytes, or a memory type the device lacks: the error create would give.
  return built ? vulkanError("gi::predictMemory", built) : Error{};
}

void destroy(Module* m) {
  if (!m) return;
  destroyModuleResources(*m);
  delete m;
}

Error setSettings(Module* m, const Settings& settings) {
  if (Error e = validate(settings)) return e;
  // Programs another thread prepares (gi::preparePrograms) are created under this lock.
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  // Build what the new settings need beside what frames in flight still
  // read; only once all of it exists does the old part retire.
  if (vk::Status s = createPrograms(*m, settings)) return vulkanError("gi::setSettings", s);
  SizedResources sized;
  const MethodPlan plan = planMethod(m->desc.scene, settings);
  bool newSized = sizedResourcesNeeded(plan, settings, m->desc) != m->sized.needs;
  if (newSized)
    if (vk::Status s = createSizedResources(*m, settings, m->desc.maxWidth, m->desc.maxHeight, m->outputs, sized))
      return vulkanError("gi::setSettings", s);
  HashGrid hash;
  bool newHash = hashGridChanges(*m, settings);
  vk::Status s = newHash ? createHashGridFor(*m, settings, m->desc.maxWidth, m->desc.maxHeight, hash) : vk::Status{};
  if (s) {
    destroyHashGrid(m->gpu, hash);
    destroySizedResources(m->gpu, sized);
    return vulkanError("gi::setSettings", s);
  }
  if (newSized) replaceSized(*m, sized);
  if (newHash || (!usesHashGrid(settings.method) && m->hash.capacity)) replaceHashGrid(*m, hash);  // none: freed
  // Only a change that makes the accumulated light wrong restarts it: another method, new images, or a
  // setting the catalogue marks (SettingInfo::restartsHistory). The budget's sample counts keep it.
  bool restart = newSized || settings.method != m->settings.method;
  for (const SettingInfo& info : settingCatalogue())
    restart = restart || (info.restartsHistory && info.get(settings) != info.get(m->settings));
  m->settings = settings;
  m->plan = plan;
  if (restart) dropHistory(*m);
  return {};
}

Error setScene(Module* m, const SceneDesc& scene) {
  if (Error e = checkScene(scene, "gi::setScene scene")) return e;
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  const ModuleDesc previousDesc = m->desc;
  m->desc.scene = scene;
  if (Error e = checkFeatures(*m)) {
    m->desc = previousDesc;
    return e;
  }
  // Programs change only with what they are specialised on or built against.
  const bool rebuild = sceneSpecialization(scene) != sceneSpecialization(previousDesc.scene) ||
                       scene.layout != previousDesc.scene.layout || scene.traversal != previousDesc.scene.traversal;
  std::vector<vk::ComputeProgram> previous;
  if (rebuild)
    for (vk::ComputeProgram* p : scenePrograms(*m)) previous.push_back(std::exchange(*p, vk::ComputeProgram{}));
  vk::Status s = createPrograms(*m, m->settings);
  SizedResources sized;                                            // the glossy images follow the scene's materials
  const MethodPlan plan = planMethod(m->desc.scene, m->settings);  // the scene's facts are part of it
  const bool newSized = sizedResourcesNeeded(plan, m->settings, m->desc) != m->sized.needs;
  if (!s && newSized) s = createSizedResources(*m, m->settings, m->desc.maxWidth, m->desc.maxHeight, m->outputs, sized);
  if (s) {
    destroySizedResources(m->gpu, sized);
    if (rebuild) {
      size_t i = 0;
      for (vk::ComputeProgram* p : scenePrograms(*m)) {
        vk::destroyComputeProgram(m->gpu, *p);
        *p = std::move(previous[i++]);
      }
    }
    m->desc = previousDesc;
    return vulkanError("gi::setScene", s);
  }
  if (rebuild) {
    auto old = std::make_shared<std::vector<vk::ComputeProgram>>(std::move(previous));
    retire(*m, [old](vk::Device& g) {
      for (vk::ComputeProgram& p : *old) vk::destroyComputeProgram(g, p);
    });
  }
  if (newSized) replaceSized(*m, sized);
  m->plan = plan;
  dropHistory(*m);
  return {};
}

Error resize(Module* m, uint32_t width, uint32_t height) {
  if (Error e = checkSize("gi::resize width × height", width, height)) return e;
  if (width == m->width && height == m->height) return {};
  if (width <= m->desc.maxWidth && height <= m->desc.maxHeight) {
    // Dynamic resolution: a new render rectangle in the same images. Nothing is allocated, the outputs
    // stay, and the histories are reprojected across the change (last frame's size is the previous camera's);
    // anhpsf's continued paths, which belong to pixels, restart.
    m->width = width;
    m->height = height;
    m->hash.walksCleared = false;
    return {};
  }
  // Beyond the largest size: every per-pixel image, and the hash map, at the new largest size.
  const std::lock_guard<std::mutex> lock(m->programsMutex);  // the screen filters' sets read their layout
  const uint32_t maxWidth = std::max(width, m->desc.maxWidth), maxHeight = std::max(height, m->desc.maxHeight);
  OutputImages outputs;
  SizedResources sized;
  HashGrid hash;
  vk::Status built = createOutputImages(m->gpu, maxWidth, maxHeight, m->desc, outputs);
  if (!built) built = createSizedResources(*m, m->settings, maxWidth, maxHeight, outputs, sized);
  if (!built && m->plan.hashGrid) built = createHashGridFor(*m, m->settings, maxWidth, maxHeight, hash);
  if (built) {
    destroyHashGrid(m->gpu, hash);
    destroySizedResources(m->gpu, sized);
    destroyOutputImages(m->gpu, outputs);
    return vulkanError("gi::resize", built);
  }
  m->desc.maxWidth = maxWidth;
  m->desc.maxHeight = maxHeight;
  m->width = width;
  m->height = height;
  replaceSized(*m, sized);
  auto oldOutputs = std::make_shared<OutputImages>(m->outputs);
  retire(*m, [oldOutputs](vk::Device& g) { destroyOutputImages(g, *oldOutputs); });
  m->outputs = outputs;
  if (hash.capacity) replaceHashGrid(*m, hash);
  dropHistory(*m);
  return {};
}

void invalidate(Module* m, Invalidate what) {
  dropHistory(*m);
  if (what == Invalidate::All)
    m->hash.cleared = false;  // re-zeroed at the start of the next frame
  else if (what == Invalidate::LightsChanged)
    m->hash.forgetLight = true;  // cells, sentinels and paths stay, their light goes
}

const Settings& settings(const Module* m) { return m->settings; }

OutputScales outputScales(const Settings& s, float preExposure) {
  if (s.method == Method::AafAo) return {};
  const bool light = debugViewCatalogue()[size_t(s.debugView)].radiance;
  return {preExposure, preExposure, light ? preExposure : 1.0f};
}

Outputs outputs(const Module* m) {
  const OutputImages& o = m->outputs;
  return {o.direct.image,  o.indirect.image, o.composite.image,    o.direct.view,
          o.indirect.view, o.composite.view, m->desc.outputFormat, compositeFormat(m->desc)};
}

}  // namespace gi
