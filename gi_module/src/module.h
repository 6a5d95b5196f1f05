// The module's internal state. Passes are free functions over it; the frame
// (frame.cpp) calls them in order like a script.
#pragma once
#include <array>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "gi/catalogue.h"
#include "gi/gi.h"
#include "gi/vk/device.h"
#include "gi/vk/programs.h"
#include "gi/vk/resources.h"
#include "method_plan.h"
#include "hash_grid.h"
#include "screen_filters.h"
#include "shared/gi_frame.h"
#include "vulkan_error.h"

namespace gi {

inline constexpr uint32_t kMaxFramesInFlight = 4;
inline constexpr uint32_t kMaxPasses = 24;  // timestamped passes per frame (gif with every option: 18)

// The three outputs (gi::outputs): replaced only by resize, so an engine
// binds them once per size whatever method it switches to.
struct OutputImages {
  vk::Image direct, indirect, composite;  // ModuleDesc::outputFormat; indirect is demodulated
  bool initialised = false;               // moved to GENERAL layout
};

// The images one render size and one method need besides the outputs, the
// per-slot frame sets that bind them (and the outputs), and the screen
// filters over them. Built whole by createSizedResources and replaced whole
// (the old one retired) when the size or the set of images changes, so no
// descriptor set a frame in flight reads is ever rewritten. Images the
// method does not use are 1×1 placeholders.
struct SizedResources {
  uint32_t width = 0, height = 0;
  uint64_t needs = 0;                            // sizedResourcesNeeded() it was built for
  uint64_t frameBytes = 0;                       // the bytes of frameImages(), counted once they exist
  vk::Image historyDirectA, historyIndirectA;    // raw's still-camera mean; temporal reprojection's set A
  vk::Image historyDirectB, historyIndirectB;    // temporal reprojection's set B
  vk::Image historyGuide;                        // temporal reprojection: last frame's normal and view depth
  vk::Image svgfStateA, svgfStateB;              // svgf: its variances and history frames (sets A and B)
  vk::Image gradientSamplesA, gradientSamplesB;  // temporal gradients: each pixel's first sample (sets A and B)
  vk::Image temporalGradient;                    // temporal gradients: one texel per tile
  vk::Image temporalSpread;                      // history clamp: this frame's 3×3 luminance mean and σ
  vk::Image historyPacked;                       // the hash methods' direct history, 8 bytes a pixel
  vk::Image reservoirsA, reservoirsB;            // ReservoirSettings: the temporal pass's, one set a frame
  vk::Image frameReservoirs;                     // ReservoirSettings without the merge: the temporal pass's
  vk::Image reservoirPick;                       // ReservoirSettings: the spatial pass's light and W a pixel
  vk::Image noisyIndirect;                       // demodulated indirect before filtering
  vk::Image guidance, position, debug;           // filter guidance, world position, filter debug/temp
  vk::Image aafParams;                           // AAF per-pixel z_min, z_max (metres), samples, β (metres)
  vk::Image aafGlossy, aafGlossyEdge;            // AAF specular terms
  // Packed outputs (outputsPacked): the passes' direct and indirect light, half floats with an alpha, which
  // the composite pass copies into the engine's outputs; written and read within a frame.
  vk::Image workDirect, workIndirect;
  ScreenFilters filters;                     // methods with a screen-space filter
  vk::DescriptorSets frameSets;              // set 1, two per frame slot (frameSet)
  GBufferViews bound[kMaxFramesInFlight]{};  // G-buffer views written into each slot's set
  bool initialised = false;                  // images moved to GENERAL layout
};

// Placeholders that gi::recordProgramWarmup binds to its empty dispatches
// (1×1 images, a minimal hash map), so that warming a method's programs
// needs none of its real resources: held until gi::finishProgramWarmup.
struct WarmupResources {
  OutputImages outputs;
  SizedResources sized;
  HashGrid hash;
  vk::Image gbuffer;  // every G-buffer binding's view
  bool built = false;
};

// Something replaced while frames may still read it, and the number of
// frames recorded when it was replaced: it is released once those have completed.
struct Retired {
  uint64_t recordedFrames = 0;
  std::function<void(vk::Device&)> release;
};

// Per frame slot: what the stats of the frame recorded there need.
struct FrameSlot {
  uint32_t frameIndex = 0;
  bool recorded = false;
  std::vector<Pass> passes;  // recorded, in order (timestamps for the first kMaxPasses)
  uint32_t history = 0, spp = 0;
  Method method = Method::Raw;
  float hashSecondaryWidth = 1.0f;  // the hash methods' later cells' width (gi::hashSecondaryWidth)
  float skyVisibility = 1.0f;       // GiFrameConstants::skyVisibility the frame used
};

// The sky's visibility from the reservoirs' sky picks (reservoirs.sky; frame.cpp's updateSkyVisibility):
// picks and hits counted over completed frames until there are enough for a ratio.
struct SkyVisibility {
  uint64_t tested = 0, visible = 0;  // picks counted since the ratio was last taken, and those that saw the sky
  float ratio = 1.0f;                // GiFrameConstants::skyVisibility: 1 until measured
};

struct Module {
  vk::Device gpu;  // the engine's device through the module's own function table
  ModuleDesc desc;
  Settings settings;
  MethodPlan plan;                                 // planMethod(desc.scene, settings): what the frame runs
  uint32_t width = 0, height = 0;                  // the render size now (desc holds the size at create)
  uint32_t previousWidth = 0, previousHeight = 0;  // the last recorded frame's: what its histories cover

  OutputImages outputs;
  SizedResources sized;       // built over `outputs`
  HashGrid hash;              // created on first use of a hash method; persists across frames
  vk::Buffer frameConstants;  // host-visible GiFrameConstants, one per slot
  VkDeviceSize frameConstantsStride = 0;
  vk::Buffer counters;                                 // host-visible GiCounters[1 + slots]: live, then per-slot copies
  VkDescriptorSetLayout frameLayout = VK_NULL_HANDLE;  // set 1

  // Programs (programs.h), each created when settings first need it and kept;
  // created under programsMutex (gi::preparePrograms may run on another thread).
  vk::ComputeProgram rawTrace, composite, guidancePass, supersample, aafSample, aafAdaptive, temporal;
  vk::ComputeProgram svgfVariance, svgfAtrous, temporalGradient, temporalSpread, reservoirs;
  vk::ComputeProgram hashInsert, hashPaths, hashClaim, hashValidate, hashResolve,
      hashLookup;                                     // hashPaths: nhpsf/anhpsf
  FilterPrograms filterPrograms;                      // the screen-space filters' (their own set layout)
  VkDescriptorSetLayout hashLayout = VK_NULL_HANDLE;  // set 2 of the hash methods' programs
  std::mutex programsMutex;
  WarmupResources warmup;  // what gi::recordProgramWarmup binds

  VkQueryPool timestamps = VK_NULL_HANDLE;  // 2 per pass per slot (null when desc.timestamps is off)
  FrameSlot slots[kMaxFramesInFlight];
  uint64_t recordedFrames = 0;  // recordFrame calls so far
  std::vector<Retired> retired;

  uint32_t historyLength = 0;      // frames in the history images (raw.accumulate)
  uint32_t reservoirFrames = 0;    // frames the reservoirs have been resampled since they started
  uint32_t temporalFrames = 0;     // frames the temporal reprojection has run since its history started
  gpu::GpuCamera historyCamera{};  // camera the history was gathered with
  SkyVisibility skyVisibility;     // measured by the reservoirs' sky picks; starts over with the history
  FrameStats lastStats;
};

// Sized resources (sized_resources.cpp). `needs` from sizedResourcesNeeded:
// the images at full size and the filters the settings use.
// Set 1 of every pass: frame constants, G-buffer, the module images, counters.
std::span<const vk::Binding> frameBindings();
uint64_t sizedResourcesNeeded(const MethodPlan& plan, const Settings& settings, const ModuleDesc& desc);
// Set 1 for a frame of `slot` whose temporal pass writes history set `writtenSet` (0: A, 1: B): where the
// frame's reservoirs and pick borrow that set's images (reservoirHomes) the two differ in those two
// bindings, and are the same otherwise.
VkDescriptorSet frameSet(const SizedResources& r, uint32_t slot, uint32_t writtenSet);
// Where the frame's reservoir set (GI_BINDING_FRAME_RESERVOIRS) and the spatial pass's pick
// (GI_BINDING_RESERVOIR_PICK) live in a frame whose temporal pass writes history set `writtenSet`; set 1
// binds each through its rg32ui view where it has one (a lender's), else its own view. Lent:
// - the history set that temporal pass overwrites later in the frame, which holds the light of the frame
//   before last until then (half-float histories: the set in direct's texels, the pick in indirect's);
// - without such a set (the hash methods' packed history, single-float histories) the direct output, which
//   the tracing passes write first, and the composite, written last, where outputsLendToReservoirs;
// - where last frame's sets are merged (raw, AAF: A and B, history), the pick alone, in the composite.
// Otherwise frameReservoirs and reservoirPick, images of their own (1×1 where unused).
struct ReservoirHomes {
  const vk::Image* set;
  const vk::Image* pick;
};
ReservoirHomes reservoirHomes(const SizedResources& r, const OutputImages& outputs, uint32_t writtenSet);
bool outputsLendToReservoirs(const ModuleDesc& desc);
vk::Status createSizedResources(Module& m, const Settings& settings, uint32_t width, uint32_t height,
                                const OutputImages& outputs, SizedResources& out);
void destroySizedResources(vk::Device& gpu, SizedResources& r);
// Moves images not used yet (new outputs, new sized resources) to GENERAL layout.
void recordFirstUse(const vk::Device& gpu, VkCommandBuffer cmd, OutputImages& outputs, SizedResources& r);
// The images whose contents live within a frame (frameImages) start every frame from UNDEFINED, after
// every earlier command's writes: their memory may have served the engine's own resources since the
// last frame (the transient requests of ModuleDesc::deviceMemory, which an engine may alias).
void recordTransientReset(const vk::Device& gpu, VkCommandBuffer cmd, const SizedResources& r);
// The three outputs: direct and indirect in desc.outputFormat, the composite in compositeFormat(desc).
vk::Status createOutputImages(vk::Device& gpu, uint32_t width, uint32_t height, const ModuleDesc& desc,
                              OutputImages& out);
VkFormat compositeFormat(const ModuleDesc& desc);
// Direct and indirect outputs with no sign and no alpha (B10G11R11): the passes work in SizedResources'
// workDirect and workIndirect, the composite pass fills the outputs.
bool outputsPacked(const ModuleDesc& desc);
// The hash methods trace their noisy indirect straight into the indirect output (no image of its own).
bool noisyAliasesIndirect(const SizedResources& r);
// The images whose contents live within one frame (written before they are
// read, every frame); the bytes they occupy are SizedResources::frameBytes
// (FrameStats::memoryTransientBytes).
std::vector<const vk::Image*> frameImages(const SizedResources& r);
void destroyOutputImages(vk::Device& gpu, OutputImages& images);
// Hands `release` to the retire list: it runs once the frames recorded so far have completed.
void retire(Module& m, std::function<void(vk::Device&)> release);
// Runs the releases whose frames have completed (all of them with `all`).
void releaseRetired(Module& m, bool all);

// Pass helpers (frame.cpp).
PassHooks passHooks(Module& m, uint32_t slot);
void beginPass(Module& m, VkCommandBuffer cmd, uint32_t slot, Pass pass);
void endPass(Module& m, VkCommandBuffer cmd, uint32_t slot);

// The counters frame slot `slot` copied back (valid once its frame has completed; frame.cpp).
gpu::GiCounters slotCounters(const Module& m, uint32_t slot);
// gpu::HG_MODE_* of a hash method (module.cpp).
// Accumulated light is stale (settings, scene, size or invalidate): raw's
// still-camera mean and the temporal reprojection's history start over.
inline void dropHistory(Module& m) {
  m.historyLength = 0;
  m.temporalFrames = 0;
  m.reservoirFrames = 0;
  m.skyVisibility = {};
}
uint32_t hashMode(Method method);

// The scene's values, then the G-buffer's encodings (GI_SPEC_*): what every module program is specialised on (module.cpp).
std::array<uint32_t, GI_SPEC_COUNT> moduleSpecialization(const Module& m);

// Frame stats (frame_stats.cpp).
bool readFrameStats(Module& m, uint32_t slot, FrameStats& out);

// The engine's camera (camera.cpp): checked (finite, invertible view, a
// perspective projection; `what` names it), then as the passes see it.
Error checkCamera(const CameraDesc& camera, const char* what);
gpu::GpuCamera gpuCamera(const CameraDesc& now, const CameraDesc& previous, uint32_t width, uint32_t height);
glm::mat4 clipFromView(const CameraDesc& camera);  // with NDC y down the image, as the passes use it

}  // namespace gi
