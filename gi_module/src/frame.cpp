// The frame script: each pass is one dispatch and the barrier that publishes
// its writes, between a debug label and a timestamp pair.
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string_view>

#include "module.h"
#include "shared/aaf.h"

namespace gi {
namespace {

bool sameViews(const GBufferViews& a, const GBufferViews& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }
bool sameCamera(const gpu::GpuCamera& a, const gpu::GpuCamera& b) {
  return a.clipFromWorld == b.clipFromWorld && a.imageSize == b.imageSize;
}

float cosDegrees(float degrees) { return std::cos(degrees * std::numbers::pi_v<float> / 180.0f); }

// World size of a pixel per metre of view depth.
float pixelScale(const gpu::GpuCamera& c) { return 2.0f * c.tanHalfFovY / c.imageSize.y; }

// The ray budget: paths per pixel such that pixels × spp × (rays per path, as
// measured on the newest completed frame, the one that last used `slot`)
// stays within settings.rayBudget. `c`: that frame's counters (slotCounters).
uint32_t samplesWithinBudget(const Module& m, uint32_t requested, uint32_t slot, const gpu::GiCounters& c) {
  const FrameSlot& done = m.slots[slot];
  if (m.settings.rayBudget == 0 || !done.recorded || done.spp == 0) return requested;
  const double pixels = double(m.width) * m.height;
  double raysPerPath = c.raysTraced > 0 ? double(c.raysTraced) / (pixels * done.spp) : 1.0;
  double affordable = double(m.settings.rayBudget) / (pixels * raysPerPath);
  return uint32_t(std::clamp(affordable, 1.0, double(requested)));
}

// AAF's budget in samples: rayBudget over the rays per sample of the newest completed frame.
uint32_t aafSampleBudget(const Module& m, uint32_t slot, const gpu::GiCounters& c) {
  if (m.settings.rayBudget == 0 || !m.slots[slot].recorded) return 0;
  double raysPerSample = c.tracedSamples > 0 ? double(c.raysTraced) / double(c.tracedSamples) : 4.0;
  double budget = double(m.settings.rayBudget) / raysPerSample;
  return uint32_t(std::clamp(budget, 1.0, 4.0e9));
}

// The sky's visibility for the reservoirs (GiFrameConstants::skyVisibility): the sky picks the newest
// completed frame (the one that last used `slot`) tested and saw through, added to those before until there
// are kSkyPicksPerRatio, whose ratio then holds until the next. One factor for the whole frame, so the
// estimate stays unbiased (the sky's share and target only move its samples); what it measures is whether
// the sky the reservoirs pick is seen, so a closed hall under a sunny map stops trading its lamps' light for
// failed shadow rays.
constexpr uint64_t kSkyPicksPerRatio = 64;
void updateSkyVisibility(Module& m, uint32_t slot, const gpu::GiCounters& c) {
  if (!m.plan.reservoirSky || !m.slots[slot].recorded) return;
  SkyVisibility& v = m.skyVisibility;
  v.tested += c.skyPicksTested;
  v.visible += std::min(c.skyPicksVisible, c.skyPicksTested);
  if (v.tested < kSkyPicksPerRatio) return;
  const float ratio = std::clamp(float(double(v.visible) / double(v.tested)), GI_SKY_VISIBILITY_MIN, 1.0f);
  // A ratio that moves by more than 2× restarts the reservoirs' history: a kept reservoir's merge weight
  // follows its light's new target, but its M does not, so the temporal merge's 1/M would dim (or brighten)
  // the pixels for as many frames as M holds (measured in a closed room under a sunny map: 1.4× the error at
  // frame 16 after the first ratio, 1/256, without the restart).
  if (ratio > 2.0f * v.ratio || 2.0f * ratio < v.ratio) m.reservoirFrames = 0;
  v.ratio = ratio;
  v.tested = v.visible = 0;
}

// The hash map sums radiance relative to the scene's typical radiance, so dim
// and bright scenes get the same fixed-point resolution (create keeps it
// positive and finite).
float radianceScale(const Module& m) { return 1.0f / m.desc.scene.typicalRadiance; }

// The largest finite value an image of `format` holds: stores clamp to it (a half float overflows to Inf).
float largestFinite(VkFormat format) {
  return format == VK_FORMAT_R16G16B16A16_SFLOAT       ? 65504.0f
         : format == VK_FORMAT_B10G11R11_UFLOAT_PACK32 ? 65024.0f  // the 10-bit blue channel's (11-bit: 65024 too)
                                                       : FLT_MAX;
}
// What the module's own light images hold per unit of radiance: half floats radiance over the scene's
// typical radiance (in range at any scene brightness), single floats radiance as it is.
float lightScale(const Module& m, VkFormat format) {
  return format == VK_FORMAT_R16G16B16A16_SFLOAT ? radianceScale(m) : 1.0f;
}

// One pass of the frame script: label and timestamps around a dispatch and
// the barrier that publishes its writes to the next compute pass.
void runPass(Module& m, VkCommandBuffer cmd, uint32_t slot, Pass name, const vk::ComputeProgram& program,
             std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const void* push = nullptr,
             uint32_t pushSize = 0) {
  beginPass(m, cmd, slot, name);
  vk::dispatch(m.gpu, cmd, program, sets, threads, push, pushSize);
  vk::computeToComputeBarrier(m.gpu, cmd);
  endPass(m, cmd, slot);
}

template <typename Push>
void runPass(Module& m, VkCommandBuffer cmd, uint32_t slot, Pass name, const vk::ComputeProgram& program,
             std::span<const VkDescriptorSet> sets, glm::uvec2 threads, const Push& push) {
  runPass(m, cmd, slot, name, program, sets, threads, &push, sizeof(Push));
}

// The three outputs between the engine's layout (ModuleDesc::outputLayout) and the passes' GENERAL; nothing
// when the engine keeps them in GENERAL.
void moveOutputs(Module& m, VkCommandBuffer cmd, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 srcStage,
                 VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  if (from == to) return;
  for (const vk::Image* img : {&m.outputs.direct, &m.outputs.indirect, &m.outputs.composite})
    vk::imageBarrier(m.gpu, cmd, img->image, from, to, srcStage, srcAccess, dstStage, dstAccess);
}

// Slot setup: the G-buffer into this slot's set (the frame that last read
// the set has completed), the images' first layout, and the frame's start:
// everything earlier frames wrote (history, hash map, counters) is made
// visible to this frame's transfers and compute passes.
void beginFrame(Module& m, VkCommandBuffer cmd, uint32_t slot, const FrameInputs& in) {
  const vk::Device& g = m.gpu;
  SizedResources& r = m.sized;
  if (!sameViews(in.gbuffer, r.bound[slot])) {
    const VkImageLayout color = m.desc.gbuffer.colorLayout;
    for (uint32_t written : {0u, 1u})
      vk::DescriptorWriter(frameSet(r, slot, written))
          .texture(gpu::GI_BINDING_GB_NORMAL, in.gbuffer.normal, color)
          .texture(gpu::GI_BINDING_GB_ALBEDO, in.gbuffer.albedo, color)
          .texture(gpu::GI_BINDING_GB_MATERIAL, in.gbuffer.material, color)
          // Without an emission view another view fills the binding; the shaders never read it then.
          .texture(gpu::GI_BINDING_GB_EMISSION, m.desc.gbuffer.hasEmission ? in.gbuffer.emission : in.gbuffer.albedo,
                   color)
          .texture(gpu::GI_BINDING_GB_MOTION, in.gbuffer.motion, color)
          .texture(gpu::GI_BINDING_GB_DEPTH, in.gbuffer.depth, m.desc.gbuffer.depthLayout)
          .write(g);
    r.bound[slot] = in.gbuffer;
  }
  vk::memoryBarrier(g, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                        VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
  // The outputs come back from the engine's layout (its reads of the last frame's done first).
  if (m.outputs.initialised)
    moveOutputs(m, cmd, m.desc.outputLayout, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  recordFirstUse(g, cmd, m.outputs, r);
  recordTransientReset(g, cmd, r);
  if (m.timestamps) g.fn.vkCmdResetQueryPool(cmd, m.timestamps, slot * kMaxPasses * 2, kMaxPasses * 2);
  g.fn.vkCmdFillBuffer(cmd, m.counters.buffer, 0, sizeof(gpu::GiCounters), 0);
  vk::memoryBarrier(g, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

// GiFrameConstants::primaryDirect: the engine's, NEE's, or the reservoirs' for what they hold.
uint32_t primaryDirect(const MethodPlan& plan, const Settings& s) {
  if (s.indirectOnly) return gpu::GI_PRIMARY_DIRECT_NONE;
  return (plan.reservoirPunctual ? gpu::GI_PRIMARY_DIRECT_RESERVOIRS : gpu::GI_PRIMARY_DIRECT_NEE) |
         (plan.reservoirEmissive ? gpu::GI_PRIMARY_DIRECT_EMISSIVE : 0u) |
         (plan.reservoirSky ? gpu::GI_PRIMARY_DIRECT_SKY : 0u);
}

// This frame's own facts beside the method's plan (Module::plan), decided once before its passes.
struct FrameSetup {
  uint32_t slot = 0;
  uint32_t spp = 0;                 // paths per pixel within the ray budget (0 for AAF, which adapts its own)
  uint32_t aafBudget = 0;           // AAF's samples within the ray budget (0: none)
  bool accumulate = false;          // raw's running mean
  bool gradientsTraced = false;     // temporal gradients, which need last frame's samples
  float hashSecondaryWidth = 1.0f;  // the hash methods' later cells' width (gi::hashSecondaryWidth)
  // Scene, frame (set 1 in the variant for the history set this frame's temporal pass writes: frameSet's;
  // taken before that pass advances Module::temporalFrames, so passes after it bind the same set).
  std::array<VkDescriptorSet, 2> sets{};
};

void recordHashPasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, const gpu::GiFrameConstants& frame) {
  const uint32_t slot = setup.slot, spp = setup.spp;
  const float secondaryWidth = setup.hashSecondaryWidth;  // the later cells' width (gi::hashSecondaryWidth)
  const Settings& s = m.settings;
  const HpsfSettings& h = s.hpsf;
  const bool strict = h.eviction == EvictionPolicy::Strict;
  const glm::uvec2 size{m.width, m.height};
  const gpu::HgPush push{.capacity = m.hash.capacity,
                         .probeWindow = h.probeWindow,
                         .filterWidth = h.filterWidth,
                         .pixelAngle = pixelScale(frame.camera),
                         .jitter = h.jitter,
                         .normalBits = h.normalBits,
                         .stochasticLod = h.stochasticLod ? 1u : 0u,
                         .clampSigma = h.clampSigma,
                         .frameIndex = frame.frameIndex,
                         .historyCap = h.historyFrames,
                         .staleFrames = h.staleFrames,
                         .minSamples = h.minSamples,
                         .seed = s.seed,
                         .samplesPerPixel = spp,
                         .maxBounces = s.maxBounces,
                         .russianRouletteStart = s.russianRouletteStart,
                         .table = hashTableBase(m.hash, frame.frameIndex),
                         .previousTable = previousHashTableBase(m.hash, frame.frameIndex),
                         .strict = strict ? 1u : 0u,
                         .debugView = uint32_t(s.debugView),
                         .mode = hashMode(s.method),
                         .depth = s.method == Method::Nhpsf ? h.pathDepth : h.continuationDepth,
                         .secondaryWidthScale = secondaryWidth,
                         .validationInterval = strict ? 0u : h.validationInterval,
                         .radianceScale = radianceScale(m),
                         .forgetLight = m.hash.forgetLight ? 1u : 0u,
                         .normalJitter = h.normalJitter,
                         .secondaryLod = uint32_t(h.secondaryLod),
                         .historySamples = s.method == Method::Hpsf ? 0u : h.historySamples,
                         .deferredClaims = m.plan.defersHashClaims ? 1u : 0u};
  m.hash.forgetLight = false;
  VkDescriptorSet sets[] = {setup.sets[0], setup.sets[1], m.hash.set[0]};
  recordHashGridFrameStart(m.gpu, cmd, m.hash, frame.frameIndex);
  if (s.method == Method::Hpsf) {
    // Pass: paths from the G-buffer; their indirect radiance goes into the filter vertex's cell.
    runPass(m, cmd, slot, Pass::HpsfInsert, m.hashInsert, sets, size, push);
  } else {
    // Pass: path segments from the G-buffer (nhpsf: pathDepth of them; anhpsf: the primary one and
    // one of each pixel's continued path); each diffuse vertex's cell gets what its segment brings.
    runPass(m, cmd, slot, s.method == Method::Nhpsf ? Pass::NhpsfPaths : Pass::AnhpsfPaths, m.hashPaths, sets, size,
            push);
  }
  if (m.plan.defersHashClaims) {
    // Pass: the free slots that missing keys asked for become the cells of the largest keys asking.
    runPass(m, cmd, slot, Pass::HpsfClaim, m.hashClaim, sets, {m.hash.capacity, 1}, push);
  }
  if (m.plan.validatesHashCells) {
    // Pass: re-trace the sentinel rays due this frame; cut histories whose light changed.
    runPass(m, cmd, slot, Pass::HpsfValidate, m.hashValidate, sets, {m.hash.capacity, 1}, push);
  }
  // Pass: fold the frame's sums into each cell's history; evict stale cells.
  runPass(m, cmd, slot, Pass::HpsfResolve, m.hashResolve, sets, {m.hash.capacity, 1}, push);
  // Pass: each pixel reads its cell (or keeps its own sample).
  runPass(m, cmd, slot, Pass::HpsfLookup, m.hashLookup, sets, size, push);
  recordHashGridTelemetryCopy(m.gpu, cmd, m.hash, slot);
}

// Whether the reservoirs hold the sky's light this frame: a sky map resampled (reservoirs.sky) and seen by
// some of its picks (a sky the scene hides everywhere is weighed by the least visibility and left alone).
bool skyInReservoirs(const Module& m) { return m.plan.reservoirSky && m.skyVisibility.ratio > GI_SKY_VISIBILITY_MIN; }

// The primary hits' reservoirs (ReservoirSettings), before any pass that traces from the G-buffer.
void recordReservoirPasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup) {
  const Settings& s = m.settings;
  const ReservoirSettings& r = s.reservoirs;
  const uint32_t slot = setup.slot;
  const auto& sets = setup.sets;
  const bool merges = m.plan.reservoirTemporal;
  gpu::GiReservoirPush push{.mode = gpu::GI_RESERVOIR_TEMPORAL,
                            .seed = s.seed,
                            .candidates = m.plan.reservoirCandidates,
                            .temporal = merges && m.reservoirFrames > 0 ? 1u : 0u,
                            .neighbours = m.plan.reservoirNeighbours,
                            .radius = r.radius,
                            .maxHistory = skyInReservoirs(m) ? std::min(r.maxHistory, r.skyMaxHistory) : r.maxHistory,
                            .unbiased = r.unbiased ? 1u : 0u,
                            .depthTolerance = s.temporal.depthTolerance,
                            .cosNormalLimit = cosDegrees(s.temporal.normalLimitDegrees),
                            .readSet = m.reservoirFrames & 1u,
                            .pairwise = r.pairwise ? 1u : 0u,
                            .boilingFilter = r.boilingFilter,
                            // Without the merge the frame's one set serves, written then read by the spatial pass.
                            .frameSet = merges ? 0u : 1u,
                            .groupCandidates = r.groupCandidates,
                            .groupPowerShare = r.groupPowerShare};
  if (m.plan.reservoirPickPass) {
    // Pass: candidates from the light sampler, last frame's reservoir and the survivor's shadow ray: the pick
    // the tracing passes take (a spatial pass without neighbours would only keep the pixel's own).
    push.mode = gpu::GI_RESERVOIR_PICK;
    runPass(m, cmd, slot, Pass::ReservoirPick, m.reservoirs, sets, {m.width, m.height}, push);
  } else {
    // Pass: candidates from the light sampler, last frame's reservoir.
    runPass(m, cmd, slot, Pass::ReservoirTemporal, m.reservoirs, sets, {m.width, m.height}, push);
    // Pass: neighbours' reservoirs merged and the survivor's shadow ray: the pick the tracing passes take.
    push.mode = gpu::GI_RESERVOIR_SPATIAL;
    runPass(m, cmd, slot, Pass::ReservoirSpatial, m.reservoirs, sets, {m.width, m.height}, push);
  }
  m.reservoirFrames++;
}

// SVGF after its temporal accumulation (which wrote set B on odd counts).
void recordSvgfPasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, bool filterDirect) {
  const SvgfSettings& v = m.settings.svgf;
  const uint32_t slot = setup.slot;
  const auto& sets = setup.sets;
  const glm::uvec2 size{m.width, m.height};
  gpu::GiSvgfPush push{.writtenSet = m.temporalFrames & 1u,
                       .iteration = 0,
                       .sigmaLuminance = v.sigmaLuminance,
                       .sigmaNormal = v.sigmaNormal,
                       .sigmaDepth = v.sigmaDepth,
                       .iterations = v.iterations,
                       .direct = filterDirect ? 1u : 0u,
                       .debug = m.settings.debugView == DebugView::SvgfVariance ? 1u : 0u};
  // Pass: the luminance variance of direct and indirect light, from their moments.
  runPass(m, cmd, slot, Pass::SvgfVariance, m.svgfVariance, sets, size, push);
  // Passes: the à-trous iterations (the first feeds the history back).
  for (uint32_t i = 0; i < v.iterations; ++i) {
    push.iteration = i;
    runPass(m, cmd, slot, Pass::SvgfAtrous, m.svgfAtrous, sets, size, push);
  }
}

void recordFilterPasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, const gpu::GiFrameConstants& frame) {
  const Settings& s = m.settings;
  ScreenFilters& f = m.sized.filters;
  const uint32_t slot = setup.slot;
  const auto& sets = setup.sets;
  // Pass: the filters' guidance (normal, scaled depth) and world positions from the G-buffer.
  runPass(m, cmd, slot, Pass::Guidance, m.guidancePass, sets, {m.width, m.height},
          gpu::GiGuidancePush{m.plan.filterPositions ? 1u : 0u});
  // Passes: the chosen filter, noisy indirect → indirect.
  PassHooks hooks = passHooks(m, slot);
  const vk::Device& g = m.gpu;
  // The filters work in their input's units (radiance × noisyScale, or × historyScale where they read the
  // indirect history the temporal pass wrote this frame: set 0 A, set 1 B) and land in the indirect
  // output: pre-exposed, within its format. Their positions are metres over the scene extent.
  f.inputSet = m.plan.filtersReadHistory ? m.temporalFrames & 1u : 0u;  // counted past this frame's pass
  const float inputScale = m.plan.filtersReadHistory ? frame.historyScale : frame.noisyScale;
  const gpu::FilterOutputEncoding toIndirect{frame.outputScale / inputScale, frame.outputMax};
  const float positionScale = frame.depthScale;
  if (s.method == Method::Sspsf) {
    const SspsfSettings& ss = s.sspsf;
    recordSspsf(g, cmd, f,
                {ss.window, ss.filterWidth, pixelScale(frame.camera), cosDegrees(ss.normalLimitDegrees), toIndirect},
                hooks);
  } else if (m.plan.aaf) {
    float cosLimit = cosDegrees(s.aaf.normalLimitDegrees);
    const uint32_t maxRadius = s.aaf.maxRadius;
    recordAafFilter(g, cmd, f, f.set[0], toIndirect, Pass::AafFilterDiffuseRows, Pass::AafFilterDiffuseColumns,
                    cosLimit, pixelScale(frame.camera), maxRadius, positionScale, hooks);
    if (m.plan.aafSpecular) {  // glossy receivers: their specular terms, with the glossy β
      recordAafFilter(g, cmd, f, f.aafGlossySets[0], kPlainOutput, Pass::AafFilterGlossyRows,
                      Pass::AafFilterGlossyColumns, cosLimit, pixelScale(frame.camera), maxRadius, positionScale,
                      hooks);
      recordAafFilter(g, cmd, f, f.aafGlossySets[1], kPlainOutput, Pass::AafFilterGlossyEdgeRows,
                      Pass::AafFilterGlossyEdgeColumns, cosLimit, pixelScale(frame.camera), maxRadius, positionScale,
                      hooks);
    }
  } else if (s.method == Method::Gif) {
    const GuidedFilterParams gif{.radius = s.gif.radius,
                                 .epsilonNormal = s.gif.epsilonNormal,
                                 .epsilonDepth = s.gif.epsilonDepth,
                                 .guidanceDimensions = s.gif.guidanceDimensions,
                                 .writeCoefficientView = s.debugView == DebugView::GifCoefficients,
                                 .output = toIndirect};
    recordGuidedFilter(g, cmd, f, gif, hooks);
  } else if (s.method == Method::Bilateral) {
    const BilateralSettings& b = s.bilateral;
    recordBilateral(g, cmd, f, {b.radius, b.sigmaSpatial, b.sigmaNormal, b.sigmaDepth, toIndirect}, hooks);
  } else {
    const AtrousSettings& a = s.atrous;
    // Its colour edge stop compares its input's values: σ in the same units.
    recordAtrous(g, cmd, f, toIndirect, a.iterations, a.sigmaColor * inputScale, a.sigmaNormal, a.sigmaPosition, hooks);
  }
}

// What turns the G-buffer's stored motion into pixels: GBufferDesc::motionScale times its units' pixels.
glm::vec2 motionPixelsPerUnit(const GBufferDesc& g, uint32_t width, uint32_t height) {
  const glm::vec2 size{float(width), float(height)};
  const glm::vec2 units = g.motion == MotionUnits::Uv    ? size
                          : g.motion == MotionUnits::Ndc ? 0.5f * size
                                                         : glm::vec2(1.0f);
  return units * glm::vec2(g.motionScale[0], g.motionScale[1]);
}

}  // namespace

gpu::GiCounters slotCounters(const Module& m, uint32_t slot) {
  gpu::GiCounters c;
  std::memcpy(&c, static_cast<const std::byte*>(m.counters.memory.mapped) + sizeof(gpu::GiCounters) * (1 + slot),
              sizeof(c));
  return c;
}

PassHooks passHooks(Module& m, uint32_t slot) {
  return {[&m, slot](VkCommandBuffer cmd, Pass pass) { beginPass(m, cmd, slot, pass); },
          [&m, slot](VkCommandBuffer cmd) { endPass(m, cmd, slot); }};
}

void beginPass(Module& m, VkCommandBuffer cmd, uint32_t slot, Pass pass) {
  const vk::Device& g = m.gpu;
  const char* name = passInfo(pass).name;
  uint32_t index = uint32_t(m.slots[slot].passes.size());
  m.slots[slot].passes.push_back(pass);
  if (m.desc.debugLabels && g.fn.vkCmdBeginDebugUtilsLabelEXT) {
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    g.fn.vkCmdBeginDebugUtilsLabelEXT(cmd, &label);
  }
  if (m.timestamps && index < kMaxPasses) {
    g.fn.vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, m.timestamps, (slot * kMaxPasses + index) * 2);
    // Without this barrier lavapipe stamps the start only once the pass's work
    // has run (measured: a 42 ms trace read as 0.1 ms); on GPUs it costs one
    // pipeline drain per pass, which is why timestamps can be turned off.
    vk::memoryBarrier(g, cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  }
}

void endPass(Module& m, VkCommandBuffer cmd, uint32_t slot) {
  const vk::Device& g = m.gpu;
  uint32_t index = uint32_t(m.slots[slot].passes.size()) - 1;
  if (m.timestamps && index < kMaxPasses)
    g.fn.vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, m.timestamps,
                              (slot * kMaxPasses + index) * 2 + 1);
  if (m.desc.debugLabels && g.fn.vkCmdEndDebugUtilsLabelEXT) g.fn.vkCmdEndDebugUtilsLabelEXT(cmd);
}

namespace {

// The caller's inputs, checked before anything is recorded.
Error checkFrameInputs(const Module& m, VkCommandBuffer cmd, const FrameInputs& in) {
  const GBufferViews& gb = in.gbuffer;
  if (!cmd) return {ErrorCode::MissingHandle, "gi::recordFrame: the command buffer is VK_NULL_HANDLE"};
  const bool emissionView = m.desc.gbuffer.hasEmission;
  const std::pair<VkImageView, const char*> views[] = {
      {gb.normal, "normal"},     {gb.albedo, "albedo"},
      {gb.material, "material"}, {emissionView ? gb.emission : gb.albedo, "emission"},
      {gb.motion, "motion"},     {gb.depth, "depth"}};
  for (const auto& [view, name] : views)
    if (!view)
      return {ErrorCode::MissingHandle, std::string("gi::recordFrame: inputs.gbuffer.") + name +
                                            " is VK_NULL_HANDLE (the six G-buffer views must be set; emission may be "
                                            "left out with desc.gbuffer.hasEmission = false)"};
  if (!(in.preExposure > 0.0f) || !std::isfinite(in.preExposure))
    return {ErrorCode::OutOfRange, "gi::recordFrame: inputs.preExposure = " + std::to_string(in.preExposure) +
                                       " is not a positive finite factor"};
  if (Error e = checkCamera(in.camera, "inputs.camera")) return e;
  return checkCamera(in.previousCamera, "inputs.previousCamera");
}

// The frame's constants (set 1's uniform buffer): cameras, sizes, and the scales that keep light within each
// image's format. Outputs hold radiance × pre-exposure (aaf_ao's hold ratios in [0,1]), clamped into their format.
gpu::GiFrameConstants frameConstants(const Module& m, const FrameInputs& in, const gpu::GpuCamera& camera) {
  const Settings& s = m.settings;
  const float outputScale = outputScales(s, in.preExposure).indirect;
  const float outputMax = largestFinite(m.desc.outputFormat);
  const bool noisyIsOutput = noisyAliasesIndirect(m.sized);
  const VkFormat noisyFormat = m.sized.noisyIndirect.format, historyFormat = m.sized.historyDirectA.format;
  const gpu::GpuCamera previousCamera =
      gpuCamera(in.previousCamera, in.previousCamera, m.previousWidth, m.previousHeight);
  const glm::vec2 halfSize = 0.5f * glm::vec2(float(m.width), float(m.height));
  return {camera,
          previousCamera,
          {m.width, m.height},
          in.frameIndex,
          std::max(m.desc.scene.extent, 1e-6f),
          outputScale,
          outputMax,
          noisyIsOutput ? outputScale : lightScale(m, noisyFormat),
          noisyIsOutput ? outputMax : largestFinite(noisyFormat),
          lightScale(m, historyFormat),
          largestFinite(historyFormat),
          primaryDirect(m.plan, s),
          m.plan.lightSampler,
          glm::inverse(clipFromView(in.camera)),
          motionPixelsPerUnit(m.desc.gbuffer, m.width, m.height),
          // Previous − current of the NDC shifts (jitter, off-axis), in pixels.
          m.desc.gbuffer.motionHasJitter ? glm::vec2(0.0f) : (previousCamera.ndcShift - camera.ndcShift) * halfSize,
          largestFinite(compositeFormat(m.desc)),
          m.sized.svgfStateA.format == VK_FORMAT_R32G32B32A32_UINT ? 1u : 0u,
          m.skyVisibility.ratio};
}

// Passes: the light the method starts from (AAF's samples, the hash map's paths, or raw paths).
void recordTracePasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, const gpu::GiFrameConstants& frame) {
  const Settings& s = m.settings;
  const glm::uvec2 size{m.width, m.height};
  if (m.plan.aaf) {
    // Passes: 16 stratified rays give reflector distances, β and n per pixel; then the remaining n − 16.
    const gpu::AafPush aaf{.mu = s.aaf.mu,
                           .alpha = s.aaf.alpha,
                           .sceneExtent = m.desc.scene.extent,
                           .seed = s.seed,
                           .ambientOcclusion = s.method == Method::AafAo ? 1u : 0u,
                           .sampleBudget = setup.aafBudget,
                           .maxBounces = s.maxBounces,
                           .russianRouletteStart = s.russianRouletteStart,
                           .uniformSamples = s.aaf.uniformSamples,
                           .glossy = m.plan.aafSpecular ? 1u : 0u};
    runPass(m, cmd, setup.slot, Pass::AafSample, m.aafSample, setup.sets, size, aaf);
    runPass(m, cmd, setup.slot, Pass::AafAdaptive, m.aafAdaptive, setup.sets, size, aaf);
    return;
  }
  if (m.plan.hashGrid) return recordHashPasses(m, cmd, setup, frame);
  // Pass: trace paths from the G-buffer (direct + demodulated indirect, optional temporal mean).
  const gpu::GiRawPush raw{.seed = s.seed,
                           .samplesPerPixel = setup.spp,
                           .maxBounces = s.maxBounces,
                           .russianRouletteStart = s.russianRouletteStart,
                           .historyLength = m.historyLength,
                           .maxHistory = s.raw.maxAccumulatedFrames,
                           .accumulate = setup.accumulate ? 1u : 0u,
                           .gradients = m.plan.temporalGradients ? 1u : 0u,
                           .readSet = m.temporalFrames & 1u,
                           .depthTolerance = s.temporal.depthTolerance,
                           .cosNormalLimit = cosDegrees(s.temporal.normalLimitDegrees)};
  runPass(m, cmd, setup.slot, Pass::RawTrace, m.rawTrace, setup.sets, size, raw);
  // Pass: one more path per 3×3 tile with last frame's random numbers: how much its light changed.
  if (setup.gradientsTraced)
    runPass(m, cmd, setup.slot, Pass::TemporalGradient, m.temporalGradient, setup.sets,
            {(m.width + GI_GRADIENT_TILE - 1) / GI_GRADIENT_TILE, (m.height + GI_GRADIENT_TILE - 1) / GI_GRADIENT_TILE},
            raw);
}

// Pass: last frame's light, reprojected through the motion vectors, blended into this frame's (the hash
// methods' direct light; their map holds the indirect, and their own samples are accumulated only for
// the filter clamp).
void recordTemporalPasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup) {
  const Settings& s = m.settings;
  const TemporalSettings& t = s.temporal;
  const bool svgf = s.method == Method::Svgf;
  const gpu::GiTemporalPush temporal{.readSet = m.temporalFrames & 1u,
                                     .reset = m.temporalFrames == 0 ? 1u : 0u,
                                     .minBlend = svgf ? s.svgf.alpha : t.minBlend,
                                     .depthTolerance = t.depthTolerance,
                                     .cosNormalLimit = cosDegrees(t.normalLimitDegrees),
                                     .directOnly = m.plan.packedHistory ? 1u : 0u,
                                     .direct = m.plan.noisyDirect ? 1u : 0u,
                                     .moments = svgf ? 1u : 0u,
                                     .momentsMinBlend = s.svgf.momentsAlpha,
                                     .gradients = setup.gradientsTraced ? 1u : 0u,
                                     .indirectOutput = m.plan.hashGrid ? 0u : 1u,
                                     .historyClamp = m.plan.historyClamp ? t.historyClamp : 0.0f,
                                     .historyScale = radianceScale(m),
                                     .noisyOutput = m.plan.filtersReadHistory ? 0u : 1u};
  const glm::uvec2 size{m.width, m.height};
  // Pass: this frame's samples' spread around each pixel, which the history is clamped to.
  if (m.plan.historyClamp && m.temporalFrames > 0)
    runPass(m, cmd, setup.slot, Pass::TemporalSpread, m.temporalSpread, setup.sets, size, temporal);
  runPass(m, cmd, setup.slot, Pass::Temporal, m.temporal, setup.sets, size, temporal);
  m.temporalFrames++;
}

// Pass: composite (or the chosen debug view), then gif's supersamples.
void recordCompositePasses(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, const gpu::GpuCamera& camera) {
  const Settings& s = m.settings;
  // What the filter clamp holds (TemporalSettings::filterClamp): what the method filtered, against
  // the light the temporal pass accumulated.
  uint32_t clampLight = 0;
  if (m.plan.temporalPass && m.plan.screenFilters) clampLight = gpu::GI_CLAMP_INDIRECT;
  if (m.plan.temporalPass &&
      (s.method == Method::Sspsf || m.plan.clampsHashIndirect))  // they filter filter vertices only
    clampLight = gpu::GI_CLAMP_INDIRECT | gpu::GI_CLAMP_FILTER_VERTICES;
  if (clampLight && m.plan.filtersReadHistory) clampLight |= gpu::GI_CLAMP_FROM_HISTORY;
  if (s.method == Method::Svgf && s.svgf.iterations > 0)
    clampLight = gpu::GI_CLAMP_INDIRECT | gpu::GI_CLAMP_FROM_MOMENTS |
                 (m.plan.noisyDirect && s.svgf.filterDirect ? gpu::GI_CLAMP_DIRECT : 0u);
  const gpu::GiCompositePush composite{
      .debugView = uint32_t(s.debugView),
      .ambientOcclusion = s.method == Method::AafAo ? 1u : 0u,
      .sceneExtent = m.desc.scene.extent,
      .pixelScale = pixelScale(camera),
      .aafSpecular = m.plan.aafSpecular ? 1u : 0u,
      .radiance = debugViewCatalogue()[size_t(s.debugView)].radiance ? 1u : 0u,
      .temporalWritten = m.plan.temporalPass ? m.temporalFrames & 1u : 2u,  // odd counts: this frame wrote B
      .gradients = setup.gradientsTraced ? 1u : 0u,
      .filterClamp = s.temporal.filterClamp,
      .clampLight = clampLight,
      .packedHistory = m.plan.packedHistory ? 1u : 0u,
      .historyScale = radianceScale(m),
      .svgfFrames = s.method == Method::Svgf ? 1u : 0u,
      .packedOutputs = outputsPacked(m.desc) ? 1u : 0u,
      .packedMax = largestFinite(m.desc.outputFormat),
      .writesGuide = m.plan.historyGuide && !m.plan.svgf ? 1u : 0u};
  const glm::uvec2 size{m.width, m.height};
  runPass(m, cmd, setup.slot, Pass::Composite, m.composite, setup.sets, size, composite);
  if (s.method == Method::Gif && s.gif.supersamples > 0 && s.debugView == DebugView::None) {
    // Pass: extra eye rays with their own direct light and geometry-aware indirect lookup.
    runPass(m, cmd, setup.slot, Pass::GifSupersample, m.supersample, setup.sets, size,
            gpu::GiSupersamplePush{s.seed, s.gif.supersamples});
  }
}

// The frame's end: the outputs to the engine's layout, the counters to the slot's readback copy, and what
// the next frame needs to know of this one.
void endFrame(Module& m, VkCommandBuffer cmd, const FrameSetup& setup, const FrameInputs& in) {
  vk::memoryBarrier(m.gpu, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  // The outputs to the engine's layout, visible to whatever reads them next.
  moveOutputs(m, cmd, VK_IMAGE_LAYOUT_GENERAL, m.desc.outputLayout, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  // Counters to this slot's readback copy.
  VkBufferCopy copy{0, sizeof(gpu::GiCounters) * (1 + setup.slot), sizeof(gpu::GiCounters)};
  m.gpu.fn.vkCmdCopyBuffer(cmd, m.counters.buffer, m.counters.buffer, 1, &copy);
  // The slot's counters and telemetry are read by the host once the frame's fence has signalled.
  vk::memoryBarrier(m.gpu, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);

  const Settings& s = m.settings;
  if (setup.accumulate) m.historyLength = std::min(m.historyLength + 1, s.raw.maxAccumulatedFrames);
  FrameSlot& frameSlot = m.slots[setup.slot];
  frameSlot.frameIndex = in.frameIndex;
  frameSlot.history = m.historyLength;
  frameSlot.spp = setup.spp;
  frameSlot.method = s.method;
  frameSlot.hashSecondaryWidth = setup.hashSecondaryWidth;
  frameSlot.skyVisibility = m.skyVisibility.ratio;
  frameSlot.recorded = true;
  m.previousWidth = m.width;  // the next frame's histories cover this rectangle
  m.previousHeight = m.height;
  m.recordedFrames++;
}

}  // namespace

Error recordFrame(Module* mp, VkCommandBuffer cmd, const FrameInputs& in) {
  Module& m = *mp;
  if (Error e = checkFrameInputs(m, cmd, in)) return e;
  const gpu::GpuCamera camera = gpuCamera(in.camera, in.previousCamera, m.width, m.height);
  releaseRetired(m, false);
  const Settings& s = m.settings;
  FrameSetup setup;
  setup.slot = uint32_t(m.recordedFrames % m.desc.framesInFlight);
  // Budgets read the counters this slot holds (its last frame has completed) before they are overwritten:
  // one copy out of the mapped buffer serves all three, made only where one of them reads it (with the
  // defaults, no ray budget and no sky in the reservoirs, none does).
  const bool countersRead = m.slots[setup.slot].recorded && (s.rayBudget > 0 || m.plan.reservoirSky);
  const gpu::GiCounters done = countersRead ? slotCounters(m, setup.slot) : gpu::GiCounters{};
  setup.spp = m.plan.aaf ? 0u : samplesWithinBudget(m, tracedSamplesPerPixel(s), setup.slot, done);
  setup.aafBudget = aafSampleBudget(m, setup.slot, done);
  updateSkyVisibility(m, setup.slot, done);
  setup.accumulate = s.method == Method::Raw && s.raw.temporalAccumulation;
  setup.gradientsTraced = m.plan.temporalGradients && m.temporalFrames > 0;
  setup.hashSecondaryWidth = m.plan.hashGrid ? hashSecondaryWidth(s, m.desc.maxWidth, m.desc.maxHeight) : 1.0f;
  // The temporal pass reads set readSet = temporalFrames & 1 and writes the other (GiTemporalPush).
  setup.sets = {m.desc.scene.set, frameSet(m.sized, setup.slot, 1u - (m.temporalFrames & 1u))};
  m.slots[setup.slot].passes.clear();

  const gpu::GiFrameConstants frame = frameConstants(m, in, camera);
  std::memcpy(static_cast<std::byte*>(m.frameConstants.memory.mapped) + setup.slot * m.frameConstantsStride, &frame,
              sizeof(frame));
  beginFrame(m, cmd, setup.slot, in);
  // History survives only while the view and the settings stay put.
  if (!setup.accumulate || !sameCamera(camera, m.historyCamera)) m.historyLength = 0;
  m.historyCamera = camera;
  m.sized.filters.width = m.width;  // the filters' rectangle within their images (dynamic resolution)
  m.sized.filters.height = m.height;

  if (m.plan.reservoirs) recordReservoirPasses(m, cmd, setup);
  recordTracePasses(m, cmd, setup, frame);
  if (m.plan.temporalPass) recordTemporalPasses(m, cmd, setup);
  if (s.method == Method::Svgf) recordSvgfPasses(m, cmd, setup, m.plan.noisyDirect && s.svgf.filterDirect);
  if (m.plan.screenFilters) recordFilterPasses(m, cmd, setup, frame);
  recordCompositePasses(m, cmd, setup, camera);
  endFrame(m, cmd, setup, in);
  return {};
}

}  // namespace gi
