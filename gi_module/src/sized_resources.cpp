// The module's per-size images and what binds them, built for the method the
// settings choose; and the retire list that releases replaced resources once
// no frame in flight can read them.
#include <algorithm>
#include <array>
#include <iterator>
#include <tuple>

#include "module.h"

namespace gi {
namespace {

// Working images are fp32: radiance up to 1e6 and beyond must fit before any
// pre-exposure (the outputs are in ModuleDesc::outputFormat).
constexpr VkFormat kImageFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

// How long an image's contents live. Frame: written and read within one
// frame, so its memory could be shared with anything else transient (NRD's
// "transient pool"); History: read by the next frame.
enum class Lifetime { Frame, History };

// Every module image but the outputs: its member, its binding in set 1, its
// lifetime, its format, and its bit in SizedResources::needs (its index here).
struct SizedImage {
  vk::Image SizedResources::*image;
  uint32_t binding;
  Lifetime lifetime;
  VkFormat format = kImageFormat;
  uint32_t tile = 1;  // pixels per texel along each axis
};
// Normal and view depth compared to a tolerance of several per cent: packed in 32 bits (temporal.glsl's
// giPackGuide: octahedral normal 2 × 8 bits, depth a half float).
constexpr VkFormat kGuideFormat = VK_FORMAT_R32_UINT;
// The debug views' data, or the filters' temporary image where a method writes it: half floats for
// à-trous (light in the noisy image's units) and AAF (light, and β in the position image's units),
// single floats for the views (hash keys, counts). Resolved by imageFormat(); a marker, not a format.
constexpr VkFormat kFilterTempFormat = VK_FORMAT_MAX_ENUM;
// Half floats for the screen filters' guidance: its normal in [0,1] and depth over the scene extent,
// positions relative to the camera over the scene extent (gi_guidance.comp); and for AAF's parameters:
// distances and β in metres (a relative 2^-11 moves σ by 0.05%), and the sample count n ≤ 100·μ ≤ 1600, which
// pass 1 asks for and pass 2 rounds anyway (to within 1/16 of a sample below 128, half a sample from 1024).
constexpr VkFormat kHalf = VK_FORMAT_R16G16B16A16_SFLOAT;
// The light the temporal passes blend and keep (their radiance histories, and the noisy indirect they
// read and hand the filters): ModuleDesc::historyFormat (half floats by default, holding radiance over
// the scene's typical radiance: GiFrameConstants::historyScale and noisyScale), except with raw's
// running mean, which after n frames adds 1/n of a frame and keeps single floats
// (kFullPrecisionHistory). Resolved by imageFormat().
constexpr VkFormat kRadianceHistory = VK_FORMAT_UNDEFINED;
// svgf's variances and history frames (its means ride in the histories' alphas): packed in one word
// a pixel with half-float histories, as single floats with single-float ones (gi_frame.glsl's
// giPackSvgfState). Resolved by imageFormat().
constexpr VkFormat kSvgfStateFormat = VK_FORMAT_R32_UINT;
constexpr Lifetime kFrame = Lifetime::Frame, kHistory = Lifetime::History;
constexpr SizedImage kSizedImages[] = {
    {&SizedResources::historyDirectA, gpu::GI_BINDING_HISTORY_DIRECT_A, kHistory, kRadianceHistory},
    {&SizedResources::historyIndirectA, gpu::GI_BINDING_HISTORY_INDIRECT_A, kHistory, kRadianceHistory},
    {&SizedResources::noisyIndirect, gpu::GI_BINDING_NOISY_INDIRECT, kFrame, kRadianceHistory},
    {&SizedResources::guidance, gpu::GI_BINDING_GUIDANCE, kFrame, kHalf},
    {&SizedResources::position, gpu::GI_BINDING_POSITION, kFrame, kHalf},
    {&SizedResources::debug, gpu::GI_BINDING_DEBUG, kFrame, kFilterTempFormat},
    {&SizedResources::aafParams, gpu::GI_BINDING_AAF_PARAMS, kFrame, kHalf},
    {&SizedResources::aafGlossy, gpu::GI_BINDING_AAF_GLOSSY, kFrame},
    {&SizedResources::aafGlossyEdge, gpu::GI_BINDING_AAF_GLOSSY_EDGE, kFrame},
    {&SizedResources::historyDirectB, gpu::GI_BINDING_HISTORY_DIRECT_B, kHistory, kRadianceHistory},
    {&SizedResources::historyIndirectB, gpu::GI_BINDING_HISTORY_INDIRECT_B, kHistory, kRadianceHistory},
    {&SizedResources::historyGuide, gpu::GI_BINDING_HISTORY_GUIDE, kHistory, kGuideFormat},
    {&SizedResources::svgfStateA, gpu::GI_BINDING_SVGF_STATE_A, kHistory, kSvgfStateFormat},
    {&SizedResources::svgfStateB, gpu::GI_BINDING_SVGF_STATE_B, kHistory, kSvgfStateFormat},
    {&SizedResources::gradientSamplesA, gpu::GI_BINDING_GRADIENT_SAMPLES_A, kHistory, VK_FORMAT_R32G32B32A32_UINT},
    {&SizedResources::gradientSamplesB, gpu::GI_BINDING_GRADIENT_SAMPLES_B, kHistory, VK_FORMAT_R32G32B32A32_UINT},
    {&SizedResources::temporalGradient, gpu::GI_BINDING_TEMPORAL_GRADIENT, kFrame, kImageFormat, GI_GRADIENT_TILE},
    {&SizedResources::temporalSpread, gpu::GI_BINDING_TEMPORAL_SPREAD, kFrame},
    {&SizedResources::historyPacked, gpu::GI_BINDING_HISTORY_PACKED, kHistory, VK_FORMAT_R32G32_UINT},
    {&SizedResources::reservoirsA, gpu::GI_BINDING_RESERVOIRS_A, kHistory, VK_FORMAT_R32G32B32A32_UINT},
    {&SizedResources::reservoirsB, gpu::GI_BINDING_RESERVOIRS_B, kHistory, VK_FORMAT_R32G32B32A32_UINT},
    {&SizedResources::reservoirPick, gpu::GI_BINDING_RESERVOIR_PICK, kFrame, VK_FORMAT_R32G32_UINT},
    {&SizedResources::frameReservoirs, gpu::GI_BINDING_FRAME_RESERVOIRS, kFrame, VK_FORMAT_R32G32_UINT},
};
// Beyond the image bits: which screen filters exist.
static_assert(std::size(kSizedImages) <= 26, "the image bits stay below the flags");
constexpr uint32_t kHalfFilterTemp = 1u << 26, kFullPrecisionHistory = 1u << 27;
constexpr uint32_t kNeedsFilters = 1u << 28, kNeedsGuidedStack = 1u << 29, kNeedsGlossySets = 1u << 30;
// The noisy indirect goes straight into the indirect output where no pass reads it once the output is
// written: the hash methods' lookup overwrites it pixel by pixel, svgf's temporal pass reads it pixel by
// pixel before its à-trous iterations use the output as scratch, and so does the screen filters' before
// they filter the history it wrote (MethodPlan::filtersReadHistory). Set 1's noisy-indirect
// binding then names the indirect image, and no separate image is held (except for the filter
// in | out view, which shows both).
constexpr uint32_t kNoisyIsIndirect = 1u << 31;
// Bits 32–35: the guided filter's gif.subsample, which sizes its statistics images.
constexpr uint32_t kGuidedSubsampleShift = 32;
// Bit 36: the filters read the indirect history (two filter sets, one per history set).
constexpr uint64_t kFiltersReadHistory = 1ull << 36;
// Bit 37: the frame's reservoirs and the pick borrow the history set this frame's temporal pass is about
// to overwrite (reservoirHomes).
constexpr uint64_t kReservoirsInHistory = 1ull << 37;
// Bit 38: where there is no such history set, the frame's reservoirs borrow the direct output and the pick
// the composite (reservoirHomes); where the sets are merged (history), the pick alone.
constexpr uint64_t kReservoirsInOutputs = 1ull << 38;
uint32_t guidedSubsample(uint64_t needs) { return uint32_t(needs >> kGuidedSubsampleShift) & 0xfu; }
static_assert(GIF_MAX_SUBSAMPLE <= 0xfu, "gif.subsample fits its four bits");

constexpr uint32_t bit(vk::Image SizedResources::*image) {
  for (uint32_t i = 0; i < std::size(kSizedImages); ++i)
    if (kSizedImages[i].image == image) return 1u << i;
  return 0;
}

// The history images the frame's reservoirs and pick borrow (kReservoirsInHistory): viewed as rg32ui too.
bool lendsToReservoirs(const SizedImage& image, uint64_t needs) {
  const vk::Image SizedResources::*lenders[] = {&SizedResources::historyDirectA, &SizedResources::historyDirectB,
                                                &SizedResources::historyIndirectA, &SizedResources::historyIndirectB};
  return (needs & kReservoirsInHistory) &&
         std::find(std::begin(lenders), std::end(lenders), image.image) != std::end(lenders);
}

// Set 1: the frame constants, the G-buffer, the outputs and the counters, then one storage image per
// entry of kSizedImages (derived, so an image and its binding are declared once).
constexpr vk::Binding kFixedFrameBindings[] = {
    {gpu::GI_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
    {gpu::GI_BINDING_GB_NORMAL, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_GB_ALBEDO, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_GB_MATERIAL, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_GB_EMISSION, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_GB_MOTION, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_GB_DEPTH, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
    {gpu::GI_BINDING_OUT_DIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_OUT_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_OUT_COMPOSITE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {gpu::GI_BINDING_PACKED_DIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {gpu::GI_BINDING_PACKED_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
};
constexpr auto kFrameBindings = [] {
  std::array<vk::Binding, std::size(kFixedFrameBindings) + std::size(kSizedImages)> all{};
  size_t n = 0;
  for (const vk::Binding& b : kFixedFrameBindings) all[n++] = b;
  for (const SizedImage& image : kSizedImages) all[n++] = {image.binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
  return all;
}();
static_assert(std::size(kFrameBindings) == gpu::GI_BINDING_COUNT, "every binding of set 1 once");

}  // namespace

std::span<const vk::Binding> frameBindings() { return kFrameBindings; }

uint64_t sizedResourcesNeeded(const MethodPlan& plan, const Settings& s, const ModuleDesc& desc) {
  uint64_t need = 0;
  const bool noisyReadAfterOutput = s.debugView == DebugView::FilterInOut;
  if (!noisyReadAfterOutput && ((plan.hashGrid && !plan.clampsHashIndirect) || plan.svgf || plan.filtersReadHistory))
    need |= kNoisyIsIndirect;
  else
    need |= bit(&SizedResources::noisyIndirect);
  if (s.method == Method::Raw && s.raw.temporalAccumulation)
    need |= bit(&SizedResources::historyDirectA) | bit(&SizedResources::historyIndirectA) | kFullPrecisionHistory;
  if (plan.packedHistory) {
    need |= bit(&SizedResources::historyPacked);
  } else if (plan.temporalPass) {
    need |= bit(&SizedResources::historyDirectA) | bit(&SizedResources::historyDirectB);
    // The hash methods reproject their direct light only, and with the filter clamp accumulate their samples.
    if (!plan.hashGrid || plan.clampsHashIndirect)
      need |= bit(&SizedResources::historyIndirectA) | bit(&SizedResources::historyIndirectB);
  }
  if (plan.historyGuide) need |= bit(&SizedResources::historyGuide);
  if (plan.screenFilters) need |= bit(&SizedResources::guidance);
  if (plan.filterPositions) need |= bit(&SizedResources::position);
  // The filters' temp image (set 1's debug image): à-trous ping-pongs through it and AAF's row pass writes
  // it; gif writes it only for its coefficient view, bilateral and sspsf never.
  if (s.method == Method::Atrous || plan.aaf) need |= bit(&SizedResources::debug) | kHalfFilterTemp;
  // The hash lookup leaves its data for any debug view (the hash views read it).
  if (plan.hashGrid && s.debugView != DebugView::None) need |= bit(&SizedResources::debug);
  if (plan.svgf) need |= bit(&SizedResources::svgfStateA) | bit(&SizedResources::svgfStateB);
  if (plan.temporalGradients)
    need |= bit(&SizedResources::gradientSamplesA) | bit(&SizedResources::gradientSamplesB) |
            bit(&SizedResources::temporalGradient);
  if (plan.historyClamp) need |= bit(&SizedResources::temporalSpread);
  // AAF's pass 1 hands its sample sums to pass 2 in the noisy indirect (aaf.glsl's aafStorePartial).
  if (plan.aaf) need |= bit(&SizedResources::aafParams);
  // The temporal reservoirs: two sets of history where last frame's are merged, else one set of the frame's
  // in half the bytes (GI_BINDING_FRAME_RESERVOIRS), which with the pick borrows the temporal pass's
  // history set where there is one (half floats: the same eight bytes a texel as their rg32ui), else the
  // direct output, and the pick the composite (where the sets are merged, the pick alone).
  const bool frameSet = plan.reservoirs && !plan.reservoirTemporal;
  const bool borrowHistory =
      frameSet && plan.temporalPass && !plan.packedHistory && desc.historyFormat == VK_FORMAT_R16G16B16A16_SFLOAT;
  if (plan.reservoirTemporal) need |= bit(&SizedResources::reservoirsA) | bit(&SizedResources::reservoirsB);
  if (borrowHistory)
    need |= kReservoirsInHistory;
  else if (plan.reservoirs && outputsLendToReservoirs(desc))
    need |= kReservoirsInOutputs;
  else if (plan.reservoirs)
    need |= bit(&SizedResources::reservoirPick) | (plan.reservoirTemporal ? 0 : bit(&SizedResources::frameReservoirs));
  if (plan.aafSpecular) need |= bit(&SizedResources::aafGlossy) | bit(&SizedResources::aafGlossyEdge);
  // Debug views read their source at full size whatever the method (zero where it does not write).
  switch (s.debugView) {
    case DebugView::Guidance:
    case DebugView::GuidanceDepth: need |= bit(&SizedResources::guidance); break;
    case DebugView::AafZMin:
    case DebugView::AafZMax:
    case DebugView::AafSamples:
    case DebugView::AafFilterWidth: need |= bit(&SizedResources::aafParams); break;
    case DebugView::GifCoefficients:
    case DebugView::HashCells:
    case DebugView::HashLod:
    case DebugView::HashSamples:
    case DebugView::HashFound:
    case DebugView::HashOccupancy:
    case DebugView::ContinuationDepth:
    case DebugView::SvgfVariance: need |= bit(&SizedResources::debug); break;
    case DebugView::TemporalHistory:  // the packed history's frames reach the composite in the direct output
      if (!plan.packedHistory) need |= bit(&SizedResources::historyDirectA) | bit(&SizedResources::historyDirectB);
      break;
    case DebugView::TemporalGradient: need |= bit(&SizedResources::temporalGradient); break;
    default: break;
  }
  if (plan.screenFilters) need |= kNeedsFilters;
  if (plan.filtersReadHistory) need |= kFiltersReadHistory;
  if (s.method == Method::Gif) need |= kNeedsGuidedStack | uint64_t(s.gif.subsample) << kGuidedSubsampleShift;
  if (plan.aafSpecular) need |= kNeedsGlossySets;
  return need;
}

namespace {

VkFormat imageFormat(const Module& m, const SizedImage& image, uint64_t needs) {
  if (image.format == kFilterTempFormat)
    return needs & kHalfFilterTemp ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
  if (image.format == kSvgfStateFormat)
    return m.desc.historyFormat == VK_FORMAT_R16G16B16A16_SFLOAT ? kSvgfStateFormat : VK_FORMAT_R32G32B32A32_UINT;
  if (image.format != kRadianceHistory) return image.format;
  return needs & kFullPrecisionHistory ? VK_FORMAT_R32G32B32A32_SFLOAT : m.desc.historyFormat;
}

// The images the passes write their direct and indirect light into: the outputs, or where those are
// packed the working images of `r`.
const vk::Image& workingDirect(const OutputImages& outputs, const SizedResources& r) {
  return r.workDirect.memory.size ? r.workDirect : outputs.direct;
}
const vk::Image& workingIndirect(const OutputImages& outputs, const SizedResources& r) {
  return r.workIndirect.memory.size ? r.workIndirect : outputs.indirect;
}

// The screen filters over the images of `r`, with the parts `r.needs` asks for.
vk::Status createFilters(Module& m, const OutputImages& outputs, SizedResources& r) {
  if (!(r.needs & kNeedsFilters)) return {};
  const FilterTargets noisy{r.guidance.view, r.position.view,  r.noisyIndirect.view, workingIndirect(outputs, r).view,
                            r.debug.view,    r.aafParams.view, m.counters.buffer};
  // Reading the history: set 0 filters the A set the temporal pass wrote, set 1 the B set.
  FilterTargets history[2] = {noisy, noisy};
  history[0].input = r.historyIndirectA.view;
  history[1].input = r.historyIndirectB.view;
  GI_TRY(createScreenFilters(m.gpu, m.filterPrograms, r.width, r.height,
                             r.needs & kFiltersReadHistory ? std::span<const FilterTargets>(history)
                                                           : std::span<const FilterTargets>(&noisy, 1),
                             r.filters));
  if (r.needs & kNeedsGlossySets) {
    // The glossy terms are filtered in place: β in their alpha, the filter's temp image shared.
    const FilterTargets glossy[] = {{r.guidance.view, r.position.view, r.aafGlossy.view, r.aafGlossy.view, r.debug.view,
                                     r.aafGlossy.view, m.counters.buffer},
                                    {r.guidance.view, r.position.view, r.aafGlossyEdge.view, r.aafGlossyEdge.view,
                                     r.debug.view, r.aafGlossyEdge.view, m.counters.buffer}};
    GI_TRY(createFilterSets(m.gpu, m.filterPrograms, glossy, r.filters.aafGlossySets));
  }
  if (r.needs & kNeedsGuidedStack) GI_TRY(ensureGuidedStack(m.gpu, r.filters, guidedSubsample(r.needs)));
  return {};
}

}  // namespace

bool noisyAliasesIndirect(const SizedResources& r) { return (r.needs & kNoisyIsIndirect) != 0; }

namespace {
// A reservoir binding's view of its home: a lender's rg32ui view, or an image of their own's view.
VkImageView reservoirView(const vk::Image& home) { return home.alsoView != VK_NULL_HANDLE ? home.alsoView : home.view; }
}  // namespace

ReservoirHomes reservoirHomes(const SizedResources& r, const OutputImages& outputs, uint32_t writtenSet) {
  if (r.needs & kReservoirsInHistory)
    return {writtenSet ? &r.historyDirectB : &r.historyDirectA, writtenSet ? &r.historyIndirectB : &r.historyIndirectA};
  const bool merged = (r.needs & bit(&SizedResources::reservoirsA)) != 0;
  if (r.needs & kReservoirsInOutputs) return {merged ? &r.frameReservoirs : &outputs.direct, &outputs.composite};
  return {&r.frameReservoirs, &r.reservoirPick};
}

// The direct output is first written by the tracing passes, after the spatial reservoir pass read the
// frame's reservoirs for the last time; the composite by the composite pass, after the last pass that takes
// the pick. Both are half-float outputs there, eight bytes a texel as an rg32ui reservoir (packed outputs
// have the module's working pair instead, and a packed composite holds four bytes).
bool outputsLendToReservoirs(const ModuleDesc& desc) {
  return desc.outputFormat == VK_FORMAT_R16G16B16A16_SFLOAT && compositeFormat(desc) == VK_FORMAT_R16G16B16A16_SFLOAT;
}

VkDescriptorSet frameSet(const SizedResources& r, uint32_t slot, uint32_t writtenSet) {
  return r.frameSets[slot * 2 + writtenSet];
}

namespace {
// Calls `visit` for each image whose contents live within one frame: the sized images of frame lifetime,
// then the guided filter's stack where it exists (a prediction's images have memory and no handle).
template <typename Visit>
void forEachFrameImage(const SizedResources& r, Visit&& visit) {
  for (const SizedImage& image : kSizedImages)
    if (image.lifetime == Lifetime::Frame) visit(r.*image.image);
  for (const vk::Image& stack : r.filters.a)
    if (stack.memory.size) visit(stack);
  for (const vk::Image* work : {&r.workDirect, &r.workIndirect})
    if (work->memory.size) visit(*work);
}
}  // namespace

std::vector<const vk::Image*> frameImages(const SizedResources& r) {
  std::vector<const vk::Image*> images;
  forEachFrameImage(r, [&](const vk::Image& image) { images.push_back(&image); });
  return images;
}

bool outputsPacked(const ModuleDesc& desc) { return desc.outputFormat == VK_FORMAT_B10G11R11_UFLOAT_PACK32; }

VkFormat compositeFormat(const ModuleDesc& desc) {
  return desc.compositeFormat == VK_FORMAT_UNDEFINED ? desc.outputFormat : desc.compositeFormat;
}

vk::Status createOutputImages(vk::Device& gpu, uint32_t width, uint32_t height, const ModuleDesc& desc,
                              OutputImages& out) {
  OutputImages o;
  const VkImageUsageFlags usage =
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
  // The direct output and the composite also viewed as rg32ui where they may hold the frame's reservoirs and
  // pick (outputsLendToReservoirs): created so whatever method the settings pick later.
  const VkFormat lent = outputsLendToReservoirs(desc) ? VK_FORMAT_R32G32_UINT : VK_FORMAT_UNDEFINED;
  const std::tuple<vk::Image*, VkFormat, VkFormat> images[] = {{&o.direct, desc.outputFormat, lent},
                                                               {&o.indirect, desc.outputFormat, VK_FORMAT_UNDEFINED},
                                                               {&o.composite, compositeFormat(desc), lent}};
  for (const auto& [img, format, alsoViewedAs] : images)
    if (vk::Status s = vk::createImage(gpu, {width, height}, format, usage, *img, false, alsoViewedAs)) {
      destroyOutputImages(gpu, o);
      return s;
    }
  out = o;
  return {};
}

void destroyOutputImages(vk::Device& gpu, OutputImages& o) {
  for (vk::Image* img : {&o.direct, &o.indirect, &o.composite}) vk::destroyImage(gpu, *img);
  o = OutputImages{};
}

vk::Status createSizedResources(Module& m, const Settings& settings, uint32_t width, uint32_t height,
                                const OutputImages& outputs, SizedResources& out) {
  SizedResources r;
  r.width = width;
  r.height = height;
  r.needs = sizedResourcesNeeded(planMethod(m.desc.scene, settings), settings, m.desc);
  auto build = [&]() -> vk::Status {
    for (uint32_t i = 0; i < std::size(kSizedImages); ++i) {
      const uint32_t tile = kSizedImages[i].tile;
      VkExtent2D extent =
          (r.needs >> i) & 1u ? VkExtent2D{(width + tile - 1) / tile, (height + tile - 1) / tile} : VkExtent2D{1, 1};
      GI_TRY(
          vk::createImage(m.gpu, extent, imageFormat(m, kSizedImages[i], r.needs),
                          VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                              VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                          r.*kSizedImages[i].image, kSizedImages[i].lifetime == Lifetime::Frame,
                          lendsToReservoirs(kSizedImages[i], r.needs) ? VK_FORMAT_R32G32_UINT : VK_FORMAT_UNDEFINED));
    }
    if (outputsPacked(m.desc))
      for (vk::Image* work : {&r.workDirect, &r.workIndirect})
        GI_TRY(vk::createImage(
            m.gpu, {width, height}, VK_FORMAT_R16G16B16A16_SFLOAT,
            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, *work,
            true));
    GI_TRY(vk::createDescriptorSets(m.gpu, kFrameBindings, m.desc.framesInFlight * 2, r.frameSets, m.frameLayout));
    for (uint32_t index = 0; index < m.desc.framesInFlight * 2; ++index) {
      const uint32_t slot = index / 2, written = index % 2;
      vk::DescriptorWriter w(r.frameSets[index]);
      w.buffer(gpu::GI_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, m.frameConstants.buffer,
               slot * m.frameConstantsStride, sizeof(gpu::GiFrameConstants));
      // The shaders' live counter is the first GiCounters; the others are per-slot copies for readback.
      w.buffer(gpu::GI_BINDING_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m.counters.buffer, 0,
               sizeof(gpu::GiCounters));
      w.storageImage(gpu::GI_BINDING_OUT_DIRECT, workingDirect(outputs, r).view);
      w.storageImage(gpu::GI_BINDING_OUT_INDIRECT, workingIndirect(outputs, r).view);
      w.storageImage(gpu::GI_BINDING_OUT_COMPOSITE, outputs.composite.view);
      w.storageImage(gpu::GI_BINDING_PACKED_DIRECT, outputs.direct.view);
      w.storageImage(gpu::GI_BINDING_PACKED_INDIRECT, outputs.indirect.view);
      const ReservoirHomes homes = reservoirHomes(r, outputs, written);
      for (const SizedImage& image : kSizedImages) {
        const bool alias = image.image == &SizedResources::noisyIndirect && (r.needs & kNoisyIsIndirect);
        VkImageView view = alias ? workingIndirect(outputs, r).view : (r.*image.image).view;
        if (image.image == &SizedResources::frameReservoirs) view = reservoirView(*homes.set);
        if (image.image == &SizedResources::reservoirPick) view = reservoirView(*homes.pick);
        w.storageImage(image.binding, view);
      }
      w.write(m.gpu);
    }
    GI_TRY(createFilters(m, outputs, r));
    for (const vk::Image* image : frameImages(r)) r.frameBytes += image->memory.size;
    return vk::Status{};
  };
  if (vk::Status s = build()) {
    destroySizedResources(m.gpu, r);
    return s;
  }
  out = std::move(r);
  return {};
}

void recordFirstUse(const vk::Device& gpu, VkCommandBuffer cmd, OutputImages& o, SizedResources& r) {
  auto toGeneral = [&](const vk::Image& img) {
    vk::imageBarrier(gpu, cmd, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE,
                     0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  };
  if (!o.initialised)
    for (const vk::Image* img : {&o.direct, &o.indirect, &o.composite}) toGeneral(*img);
  if (!r.initialised) {
    for (const SizedImage& image : kSizedImages) toGeneral(r.*image.image);
    for (const vk::Image* work : {&r.workDirect, &r.workIndirect})
      if (work->image) toGeneral(*work);
  }
  o.initialised = r.initialised = true;
}

void recordTransientReset(const vk::Device& gpu, VkCommandBuffer cmd, const SizedResources& r) {
  // Every frame: the barriers on the stack (the sized images, the guided stack and the working pair at
  // most), one call.
  std::array<VkImageMemoryBarrier2, std::size(kSizedImages) + FILTER_STACK + 2> barriers;  // + the working pair
  uint32_t count = 0;
  forEachFrameImage(r, [&](const vk::Image& image) {
    barriers[count++] = vk::imageBarrierInfo(
        image.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  });
  if (count == 0) return;
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.imageMemoryBarrierCount = count;
  dependency.pImageMemoryBarriers = barriers.data();
  gpu.fn.vkCmdPipelineBarrier2(cmd, &dependency);
}

void destroySizedResources(vk::Device& gpu, SizedResources& r) {
  destroyScreenFilters(gpu, r.filters);
  vk::destroyDescriptorSets(gpu, r.frameSets);
  for (const SizedImage& image : kSizedImages) vk::destroyImage(gpu, r.*image.image);
  for (vk::Image* work : {&r.workDirect, &r.workIndirect}) vk::destroyImage(gpu, *work);
  r = SizedResources{};
}

void retire(Module& m, std::function<void(vk::Device&)> release) {
  m.retired.push_back({m.recordedFrames, std::move(release)});
}

void releaseRetired(Module& m, bool all) {
  // Frames recorded N = framesInFlight calls ago have completed (gi.h's
  // promise), so everything retired before the frame recorded N calls before
  // this one is no longer read.
  for (size_t i = 0; i < m.retired.size();) {
    Retired& r = m.retired[i];
    if (all || r.recordedFrames + m.desc.framesInFlight <= m.recordedFrames + 1) {
      r.release(m.gpu);
      m.retired.erase(m.retired.begin() + ptrdiff_t(i));
    } else {
      ++i;
    }
  }
}

}  // namespace gi
