// gi — a drop-in global-illumination module for Vulkan engines.
// The engine owns the instance, device, queues, the frame loop and the
// G-buffer, and describes its scene to the module (gi/scene.h), which builds
// set 0 from it (layout in shaders/shared/gpu_scene.h); the module owns its
// passes, their images and memory, and records into the engine's command
// buffer. It never submits, waits or presents.
//
// Vulkan: this header needs only <vulkan/vulkan_core.h>. Include it after your
// own Vulkan header (vulkan.h with or without prototypes, volk.h or another
// loader); included first, it brings in vulkan_core.h as vulkan.h would. The
// module calls Vulkan only through a function table it loads from
// ModuleDesc::getInstanceProcAddr and touches no global function pointer.
//
// Frames in flight (ModuleDesc::framesInFlight = N, 1–4): recordFrame uses
// per-frame uniforms, descriptor sets, counters and timestamps in slot
// (call count mod N). Recording a frame promises that the frame recorded N
// calls earlier has completed on the GPU (the engine waited on its fence),
// as an engine with N frames in flight does anyway. All frames are submitted
// to one queue in recording order. Scene updates (gi/scene.h's
// updateInstances, updateLights, updateMeshVertices) are recorded into the
// frame's command buffer too: they never wait for the frames in flight.
//
// Barrier contract for gi::recordFrame:
//  - before: G-buffer images are in GBufferDesc::colorLayout (depth:
//    GBufferDesc::depthLayout) with their writes (colour attachment, depth
//    attachment or shader) made available to
//    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT sampled reads; the TLAS build (if
//    any) is complete for compute ray queries. The outputs are in
//    ModuleDesc::outputLayout (as the last frame left them).
//  - after: the output images are in ModuleDesc::outputLayout. GENERAL: written
//    by compute shaders, the caller barriers COMPUTE_SHADER/SHADER_STORAGE_WRITE
//    to its reader. Another layout: the module's own last barrier makes the
//    writes visible to every later command (a fragment shader's sampling
//    included), and the next recordFrame waits for every earlier command before
//    writing them again: the engine owes no barrier of its own.
//
// Deferred destruction: setSettings, resize and invalidate never need an idle
// GPU. What they replace is released once the frames that used it have
// completed (by the promise above), or at destroy.
//
// Errors: every function that can fail returns a gi::Error; a failed Vulkan
// call (out of memory included) carries its VkResult. The module never
// aborts the process. After a failed create nothing is left allocated; after
// a failed setSettings or resize the module keeps its previous settings and
// size and stays usable.
//
// Threads: a Module is not thread-safe; call every function for one module
// from one thread at a time (any thread), but for the program functions
// (preparePrograms and the warm-up, below), which may run on a second thread. Different modules may be used from
// different threads at once: each has its own function table and memory.
// validate(), version(), resultName() and the catalogues (gi/catalogue.h) are
// pure and may be called from anywhere.
#pragma once
#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "gi/device.h"
#include "gi/device_memory.h"
#include "gi/settings.h"
#include "shared/scene_modes.h"

// The API's version (gi::version(); find_package(gi 0.15)):
//   0.15: SceneCreateDesc::rebuildOffThread (degraded levels rebuilt on a worker thread, by default),
//         SceneInfo::levelRebuildRunning
//   0.14: ModuleDesc::outputFormat B10G11R11 (all three outputs packed); SceneCreateDesc::rebuildCostRatio,
//         SceneInfo::refitCostRatio and levelRebuilds (degraded refit levels rebuilt)
//   0.13: hashCapacity takes the Settings (nhpsf and anhpsf size their map from their segments);
//         hashSecondaryWidth (their later cells widen past the map's cap), FrameStats::Hash::secondaryWidth
//   0.12: GifSettings::subsample (the guided filter's window statistics at 1/s resolution; default 4, so
//         gif's image differs from 0.11's: docs/RESULTS.md, "gif's statistics at 1/s")
//   0.11: holdMeshVertices (a deforming mesh at rest reads no motion)
//   0.10: device memory from the engine (ModuleDesc/SceneCreateDesc::deviceMemory), predictMemory, dynamic
//         resolution within maxWidth × maxHeight, compositeFormat
//   0.9: deformable meshes (MeshDesc::deformable, updateMeshVertices)
//   0.8: GBufferDesc::motionScale, motionHasJitter, MotionUnits::Ndc; defaults a host that sets nothing expects
//        (GlossyFlag::FromMaterial, MaterialDesc::metallic 0)
//   0.7: Settings::reservoirs (ReSTIR DI for the primary hits), Settings::lights (NEE's sampler at run time)
//   0.6: light samplers, checkBounds
//   0.5: programs readied ahead of a switch (preparePrograms, recordProgramWarmup); set 0's arrays as texel
//        buffers
//   0.4: the scene API (gi/scene.h), the G-buffer adapter, the camera as matrices
//   0.3: half-float outputs with pre-exposure
//   0.2: own function table, frames in flight, returned Vulkan errors, catalogues
#define GI_VERSION_MAJOR 0
#define GI_VERSION_MINOR 15

namespace gi {

// How set 0 is traced. The values are shared/scene_modes.h's TRAVERSAL_*, which the shaders are built for.
enum class Traversal : uint32_t {
  RayQuery = gpu::TRAVERSAL_RAY_QUERY,  // VK_KHR_ray_query against the TLAS (the device has the ray-tracing extensions)
  Compute = gpu::TRAVERSAL_COMPUTE,     // the module's BVH, walked in its shaders (any device)
};

// Set 0 and the facts the module specialises its passes on: what
// gi::sceneDesc(scene) returns for a gi::Scene (gi/scene.h).
struct SceneDesc {
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;  // set 0 per shaders/shared/gpu_scene.h
  VkDescriptorSet set = VK_NULL_HANDLE;
  bool hasEmissiveTriangles = false;  // skips emissive-light sampling when false
  uint32_t emissiveTriangles = 0;     // the emissive triangles NEE picks among (GpuSceneConstants::
                                      // emissiveTriangleCount): past ReservoirSettings::emissiveMin the
                                      // reservoirs resample them
  bool hasPunctualLights = false;     // skips the punctual-light loop when false
  bool hasAlphaMask = true;           // false: every hit is opaque (faster traversal)
  float extent = 1.0f;                // largest side of the scene bounds, metres: scales depth guidance
  bool hasGlossyMaterials = false;    // some material has a glossy lobe: AAF filters its specular term separately
  float typicalRadiance = 1.0f;       // W/(sr·m²) of lit surfaces, to within ×1000: the hash map's fixed-point
                                      // sums resolve 2^-16 of it and hold 1e9 times it
  bool hasSky = false;                // rays that leave the scene see the sky (GpuSceneConstants' sky
                                      // fields): every pass compiles the sky's NEE and misses in
  Traversal traversal = Traversal::RayQuery;        // how set 0 is traced: RayQuery (binding 0 is the TLAS) or Compute
                                                    // (the BVH bindings; the device needs no ray queries)
  bool hasComputeBvh = true;                        // set 0's BVH bindings hold the scene (false: a scene built for ray
                                                    // queries alone, SceneCreateDesc::bothTraversals off; then
                                                    // Traversal::Compute is an error)
  uint32_t lightSampler = gpu::LIGHT_SAMPLER_TREE;  // the scene's (gi::SceneCreateDesc::lightSampler)
  bool picksPunctualLightsWith[3] = {};  // under each gpu::LIGHT_SAMPLER_*, NEE picks one of several punctual
                                         // lights (power, or the tree beyond its cut): their direct light is
                                         // noisy, and the temporal passes and svgf accumulate and filter it as
                                         // area lights' (picksPunctualLights: under the scene's own sampler)
};

// The values of the SCENE_SPEC_* specialisation constants (shared/scene_modes.h) for `scene`: what every
// pipeline that binds set 0 is specialised on, the module's and an engine's own passes alike.
std::array<uint32_t, SCENE_SPEC_COUNT> sceneSpecialization(const SceneDesc& scene);

// Whether NEE picks among the scene's punctual lights under its own sampler.
inline bool picksPunctualLights(const SceneDesc& scene) {
  return scene.lightSampler <= gpu::LIGHT_SAMPLER_TREE && scene.picksPunctualLightsWith[scene.lightSampler];
}

// How the engine's G-buffer stores what the module reads. The module reads
// each image as a sampled image (texelFetch; usage SAMPLED), so any format
// below works as it is; create refuses any other (UnsupportedFormat, naming it).
// Every encoding stores world-space shading normals of unit length turned to
// face the camera (a surface seen from behind stores −n: the module lights the
// side the camera sees). Octahedral normals: e = n.xy / (|n.x| + |n.y| + |n.z|),
// folded where n.z < 0 to (1 − |e.y|, 1 − |e.x|) with the signs of e.x and e.y
// (Cigolle et al. 2014), in [−1,1]² (OctahedralSigned) or as e·0.5 + 0.5
// (Octahedral). Background pixels: LinearViewZ 0, or the far plane's depth.
enum class NormalEncoding : uint32_t {
  Xyz = 0,           // world normal in rgb, [-1,1]: R16G16B16A16_SFLOAT (ours), R32G32B32A32_SFLOAT,
                     // R16G16B16A16_SNORM, R8G8B8A8_SNORM
  XyzUnorm,          // normal·0.5 + 0.5: A2B10G10R10_UNORM_PACK32, A2R10G10B10_UNORM_PACK32, R8G8B8A8_UNORM,
                     // R16G16B16A16_UNORM
  Octahedral,        // octahedral in rg, [0,1]: R16G16_UNORM, R8G8_UNORM
  OctahedralSigned,  // octahedral in rg, [-1,1]: R16G16_SNORM, R16G16_SFLOAT, R32G32_SFLOAT
};
enum class DepthEncoding : uint32_t {
  LinearViewZ = 0,   // view depth along −Z in metres, 0 = background: R32_SFLOAT (ours), R16_SFLOAT
  Hardware,          // the depth buffer, far = 1 = background: D32_SFLOAT, D32_SFLOAT_S8_UINT, D24_UNORM_S8_UINT,
                     // X8_D24_UNORM_PACK32, D16_UNORM (a depth-aspect view); view depth from the projection
  HardwareReversed,  // the same with reversed Z: far = 0 = background
};
// Motion vectors, after GBufferDesc::motionScale: where the surface in a pixel was last frame, less
// where it is now (previous − current; x right, y down the image, as pixels are), in one of these units.
enum class MotionUnits : uint32_t {
  Pixels = 0,  // pixels (ours)
  Uv,          // [0,1] texture coordinates: pixels / the render size
  Ndc,         // Vulkan NDC, [−1,1] across the image: pixels / half the render size
};
// Which G-buffer pixels have a glossy (GGX) lobe, for AAF's glossy receivers.
enum class GlossyFlag : uint32_t {
  AlbedoAlpha = 0,  // albedo.a ≥ 0.5 (our engine's G-buffer writes the flag there)
  FromMaterial,     // metallic > 0 or roughness < 0.9 in the material image (the default: the images a host
                    // already writes; an alpha of opacity is never read as a flag)
};
struct GBufferDesc {
  VkFormat normalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  NormalEncoding normalEncoding = NormalEncoding::Xyz;
  VkFormat albedoFormat = VK_FORMAT_R8G8B8A8_UNORM;  // linear base colour: R8G8B8A8_UNORM/_SRGB, B8G8R8A8_UNORM/_SRGB
                                                     // (an sRGB view decodes), R16G16B16A16_SFLOAT
  GlossyFlag glossy = GlossyFlag::FromMaterial;
  VkFormat depthFormat = VK_FORMAT_R32_SFLOAT;
  DepthEncoding depthEncoding = DepthEncoding::LinearViewZ;
  VkImageLayout depthLayout = VK_IMAGE_LAYOUT_GENERAL;  // or DEPTH_READ_ONLY_OPTIMAL, DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                                                        // SHADER_READ_ONLY_OPTIMAL, as the engine leaves it
  VkImageLayout colorLayout = VK_IMAGE_LAYOUT_GENERAL;  // the five colour views' (normal … motion): or
                                                        // SHADER_READ_ONLY_OPTIMAL, as the engine leaves them
  // False: the G-buffer has no emission view (GBufferViews::emission may be VK_NULL_HANDLE); the direct
  // output and the composite then hold no emission, which the engine adds itself.
  bool hasEmission = true;
  MotionUnits motion = MotionUnits::Pixels;
  // Multiplies the stored motion (x, y) before its units: finite, non-zero. {−1, −1} for current −
  // previous; {1, −1} for motion whose y runs up the image; both for both.
  float motionScale[2] = {1.0f, 1.0f};
  // Whether the motion holds the difference of the two cameras' sub-pixel jitter (motion from the
  // jittered matrices, as ours). False: the engine's motion leaves the jitter out (as DLSS and FSR take
  // it), and the module adds the difference of the jitter in CameraDesc::clipFromView and last frame's.
  bool motionHasJitter = true;
  // Material: roughness (r), metallic (g) in any unorm or float format with r
  // and g; emission: radiance towards the camera (rgb, W/(sr·m²)) in any
  // float format. Motion: rg in any float or snorm format.
};

struct ModuleDesc {
  uint32_t structSize = sizeof(ModuleDesc);  // leave as is: create refuses a desc from another version of this header
  // The engine's loader entry point (vkGetInstanceProcAddr from the loader,
  // volk or the engine's own table): the module loads its functions through it.
  PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;  // with the features and extensions of gi/device.h
  uint32_t width = 0, height = 0;    // render size in pixels, [1, 16384]
  // Largest render size (dynamic resolution); 0 = width/height. Every per-pixel image (the outputs
  // included) and the hash methods' per-pixel buffers are allocated at this size, and resize() within
  // it allocates nothing and keeps the history; the render size is the top-left width × height of them.
  uint32_t maxWidth = 0, maxHeight = 0;
  uint32_t framesInFlight = 2;  // [1, 4]: frames the engine records before waiting on the oldest
  SceneDesc scene;
  bool debugLabels = false;  // VK_EXT_debug_utils is enabled on the instance: label every pass
  bool timestamps = true;    // time every pass (FrameStats::passes); off: no query pool, no timing barriers
  bool checkBounds = false;  // every hash-map index, image coordinate, scene-array index and texture index
      // checked against its size, one outside counted (FrameStats::boundsViolations) and kept inside: for tests and
      // bug hunts (shaders/module/bounds.glsl); off, the checks are compiled away
  uint64_t memoryBudgetBytes = 0;  // device memory the module may hold; 0 = no limit. Beyond it calls fail
                                   // with VK_ERROR_OUT_OF_DEVICE_MEMORY, as a full heap would
  const VkAllocationCallbacks* allocationCallbacks = nullptr;  // passed to every vkCreate*/vkAllocateMemory
  // Set (allocate and free): every buffer and image takes its memory from the engine (gi/device_memory.h),
  // one request per resource; the module allocates no device memory of its own. memoryBudgetBytes still
  // applies, to the sum of the requests.
  DeviceMemoryCallbacks deviceMemory;
  VkPipelineCache pipelineCache = VK_NULL_HANDLE;  // the engine's; used for every pipeline
  // The feature chain the engine passed to vkCreateDevice (gi/device.h fills
  // it). When given, create checks that it enables what the module needs;
  // when null, create checks what the device supports.
  const VkPhysicalDeviceFeatures2* enabledFeatures = nullptr;
  GBufferDesc gbuffer;  // the engine's G-buffer formats and encodings (defaults: ours, shared/gbuffer.h)
  // Format of the three output images: VK_FORMAT_R16G16B16A16_SFLOAT (half
  // the memory; set FrameInputs::preExposure so the light stays within
  // ±65504), VK_FORMAT_R32G32B32A32_SFLOAT, or B10G11R11_UFLOAT_PACK32 where the
  // device can store to it (as compositeFormat below; the module then works in two half-float images of
  // its own, 16 bytes a pixel that live within a frame (FrameStats::memoryTransientBytes), and its
  // composite pass copies them into the direct and indirect outputs, negative light as 0). Anything
  // else: UnsupportedFormat.
  VkFormat outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  // Format of the composite alone: VK_FORMAT_UNDEFINED (outputFormat), R16G16B16A16_SFLOAT,
  // R32G32B32A32_SFLOAT, or B10G11R11_UFLOAT_PACK32 where the device can store to it (an engine's HDR
  // target: 4 bytes a pixel, steps of at most 1/64 of a value, no sign, no alpha, up to 65024; where
  // not, UnsupportedFormat). The direct and indirect outputs stay in outputFormat.
  VkFormat compositeFormat = VK_FORMAT_UNDEFINED;
  // The layout the engine keeps the three outputs in between frames: GENERAL, SHADER_READ_ONLY_OPTIMAL
  // (it samples them) or TRANSFER_SRC_OPTIMAL (it copies them). recordFrame moves them to GENERAL after
  // every earlier command (the engine's reads of the last frame's outputs included) and back to this
  // layout at its end, visible to every later command's reads (Barrier contract above).
  VkImageLayout outputLayout = VK_IMAGE_LAYOUT_GENERAL;
  // Format of the light the temporal passes blend and keep: their radiance
  // histories (gif, bilateral, à-trous, sspsf, svgf; the hash methods'
  // filter clamp) and the noisy indirect the filters read:
  // VK_FORMAT_R16G16B16A16_SFLOAT (radiance over SceneDesc::typicalRadiance,
  // up to 65504 times it; half the memory) or VK_FORMAT_R32G32B32A32_SFLOAT.
  // raw's running mean keeps single floats whatever this says.
  VkFormat historyFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
};

// G-buffer views in the formats and encodings of ModuleDesc::gbuffer, GENERAL
// layout (depth: GBufferDesc::depthLayout), sampled images; at least the render size, which the module
// reads from their top left (images of the largest size serve every size of dynamic resolution).
struct GBufferViews {
  VkImageView normal, albedo, material, emission, motion, depth;
};

// A camera as the engine rendered the G-buffer with it. Matrices are plain
// arrays, column-major: element [column * 4 + row] (GLM's, GLSL's and
// DirectX-math-transposed layout), acting on column vectors.
struct CameraDesc {
  float viewFromWorld[16];  // world → view; view space is right-handed, looking down −Z
  // view → Vulkan clip space, perspective (clip w = −z_view), depth in [0,1]
  // forward or reversed, finite or infinite far plane, with the frame's
  // sub-pixel jitter (TAA, upscalers) and any off-axis shift in it. NDC y runs
  // down the image (Vulkan's standard viewport); a y-up projection drawn with
  // a negative-height viewport (P[1][1] > 0) is taken as that flip.
  float clipFromView[16];
};

struct FrameInputs {
  GBufferViews gbuffer;
  CameraDesc camera;          // this frame's
  CameraDesc previousCamera;  // last frame's; equal to `camera` on the first frame
  uint32_t frameIndex = 0;    // increases by one per frame
  // The outputs hold radiance × preExposure, (0, ∞) finite. With half-float
  // outputs pass the exposure the engine will apply (its last frame's, as
  // engines do for TAA and upscalers), so radiance maps near 1: stored values
  // clamp at ±65504, and below about 6e-5 they lose precision (half-float
  // subnormals). Default 1: the outputs hold W/(sr·m²) as they are.
  float preExposure = 1.0f;
};

// Module-owned images in ModuleDesc::outputFormat, GENERAL layout after
// recordFrame, usage STORAGE | SAMPLED | TRANSFER_SRC, ModuleDesc::maxWidth × maxHeight (the frame is
// its top-left render size; gi::resize), rgb = light, a = 1:
//   direct    emission + direct light of the primary hit, W/(sr·m²) × preExposure
//   indirect  demodulated indirect light (the light a white Lambertian surface
//             would reflect), × preExposure; multiply by the diffuse albedo
//   composite direct + diffuse albedo × indirect (+ AAF's glossy term) × preExposure,
//             or the debug view the settings pick (views that are not light,
//             gi::debugViewCatalogue()[v].radiance = false, hold pictures scaled to [0,1] for display,
//             unscaled by pre-exposure; a count past its scale reads above 1)
// aaf_ao: indirect holds occlusion and composite AO = 1 − occlusion, in [0,1], unscaled.
struct Outputs {
  VkImage direct, indirect, composite;
  VkImageView directView, indirectView, compositeView;
  VkFormat format;           // ModuleDesc::outputFormat: the direct and indirect outputs'
  VkFormat compositeFormat;  // ModuleDesc::compositeFormat (outputFormat where that is UNDEFINED)
};

struct PassTiming {
  std::string name;
  double ms = 0.0;
  bool tracesRays = false;  // a path-tracing pass: its time is what Mrays/s divide by
};

struct FrameStats {
  uint32_t frameIndex = 0;         // the completed frame these numbers describe
  std::vector<PassTiming> passes;  // GPU time per pass, in recording order
  double totalMs = 0.0;
  uint64_t raysTraced = 0;
  uint32_t accumulatedFrames = 0;  // frames of history behind the median pixel, this one included: raw's running
                                   // mean, or the temporal passes' per-pixel history (63 reads "63 or more"); 0
                                   // where the method keeps none (aaf, a hash method's indirect light)
  uint32_t samplesPerPixel = 0;    // paths per pixel actually traced (after the ray budget; AAF: the mean)
  uint32_t sanitized = 0;          // non-finite G-buffer pixels and path samples dropped (treated as background)
  uint32_t boundsViolations = 0;   // ModuleDesc::checkBounds: accesses outside a buffer or image (0 unless a bug)
  struct SkyPicks {                // reservoirs.sky: the pixels whose reservoir picked a sky direction
    uint32_t tested = 0;           // their shadow rays traced this frame
    uint32_t visible = 0;          // of those, rays that saw the sky
    float visibility = 1.0f;       // the sky's measured visibility this frame weighed its share and target by:
                                   // recent frames' visible / tested, in [1/256, 1]; 1 until measured
  } skyPicks;
  uint64_t memoryBytes = 0;           // device memory the module holds (its blocks), bytes
  uint64_t memoryUsedBytes = 0;       // of that, bytes its buffers and images occupy
  uint64_t memoryTransientBytes = 0;  // of those, images whose contents live within one frame (NRD's transient
                                      // pool); the rest carries history, the hash map, or is an output
  uint32_t deviceAllocations = 0;     // vkAllocateMemory blocks behind memoryBytes
  struct Hash {                       // HPSF hash map telemetry (zero for other methods)
    uint32_t capacity = 0;            // cells
    float secondaryWidth = 0.0f;      // the cells after the first vertex are this much wider (gi::hashSecondaryWidth)
    uint32_t occupied = 0;            // live cells after this frame's resolve
    uint32_t inserts = 0;             // samples stored
    uint32_t failedInserts = 0;       // samples that found no slot within the probe window
    uint32_t claimed = 0;             // hpsf.deferred_claims: cells made after this frame's inserts
    float meanProbe = 0.0f;           // slots probed per successful insert
    uint32_t maxProbe = 0;
    uint32_t evicted = 0;                // cells removed this frame
    uint32_t overflows = 0;              // samples clamped to the fixed-point range
    uint32_t staleResets = 0;            // cells whose history the stale-radiance check cut short this frame
    double transported = 0.0;            // anhpsf: Σ luminance carried by continuation segments this frame
    float meanContinuationDepth = 0.0f;  // anhpsf: mean segments of the pixels' continued paths
    uint32_t reads = 0;                  // nhpsf/anhpsf: map reads at scatter vertices
    uint32_t readMisses = 0;             // of those, reads that found no usable cell (their light is missing)
    float occupancy() const { return capacity ? float(occupied) / float(capacity) : 0.0f; }
  } hash;
};

enum class ErrorCode : uint32_t {
  None = 0,
  MissingHandle,
  ZeroSize,
  SizeTooLarge,
  OutOfRange,
  UnknownMethod,
  NotPowerOfTwo,
  MissingFeature,     // the device lacks (or the engine did not enable) a feature in gi/device.h; the message names it
  VersionMismatch,    // a desc built against another version of gi.h
  VulkanCall,         // a Vulkan call failed: Error::result says how (VK_ERROR_OUT_OF_DEVICE_MEMORY, ...)
  UnsupportedFormat,  // a format the module does not accept; the message names the field
};
struct Error {
  ErrorCode code = ErrorCode::None;
  std::string message;  // names the field and the value, e.g. "settings.raw.samplesPerPixel = 0 is outside [1, 64]"
  VkResult result = VK_SUCCESS;  // VulkanCall: the failed call's result
  explicit operator bool() const { return code != ErrorCode::None; }
};

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" and the like.
const char* resultName(VkResult result);

struct Module;

// GI_VERSION_MAJOR << 16 | GI_VERSION_MINOR of the library linked, to compare
// with the header compiled against.
uint32_t version();

Error validate(const Settings& settings);
Error create(const ModuleDesc& desc, const Settings& settings, Module*& out);

// The device memory a module created from `desc` and `settings` would hold, without creating it (no
// object, no allocation, no engine callback: the memory requirements come from the device,
// vkGetDevice*MemoryRequirements, and go through the module's allocation rules). Equal to the
// FrameStats figures of such a module after its first frame: heldBytes = memoryBytes, usedBytes =
// memoryUsedBytes, transientBytes = memoryTransientBytes, deviceAllocations. With desc.deviceMemory set,
// held = used = the sum of the requests the engine will see. Not counted: the scene (gi/scene.h).
struct MemoryPrediction {
  uint64_t heldBytes = 0;          // blocks the module allocates (with deviceMemory: the engine's slices)
  uint64_t usedBytes = 0;          // what its buffers and images occupy
  uint64_t transientBytes = 0;     // of that, images whose contents live within one frame (aliasable)
  uint64_t permanentBytes = 0;     // usedBytes − transientBytes: history, the hash map, the outputs, constants
  uint32_t deviceAllocations = 0;  // vkAllocateMemory calls (0 with deviceMemory)
};
Error predictMemory(const ModuleDesc& desc, const Settings& settings, MemoryPrediction& out);
void destroy(Module* module);  // the caller ensures the GPU no longer uses it (every recorded frame completed)
Error setSettings(Module* module, const Settings& settings);
const Settings& settings(const Module* module);  // what it runs with now

// The engine's scene changed: a new set 0 (meshes, lights or the sky added or
// removed) or new facts about it (an emissive mesh streamed in:
// hasEmissiveTriangles). Programs are rebuilt only when what they are
// specialised on changes (the has* flags, the traversal, the set layout);
// the old ones are released once the frames using them complete. The old set
// 0 is the engine's to keep alive until those frames complete. Cached light
// stays: call invalidate() too when it is stale. On failure the module keeps
// the previous scene.
Error setScene(Module* module, const SceneDesc& scene);

// For engines that know what changed: drop cached light so stale radiance is
// never shown. All (geometry moved): temporal history, the hash map and
// anhpsf's continued paths start over. LightsChanged (only lights changed):
// the map keeps its cells, their sentinel rays and the continued paths, and every
// cell's mean restarts from the next frame's samples (that frame's paths still
// read the old light at their far ends; it washes out within a few frames).
// History: the screen-space histories alone restart (temporal reprojection,
// raw's running mean, svgf's, the reservoirs), the hash map keeps its light:
// a cut in the engine's camera. setSettings restarts them only for the changes
// that make them wrong (SettingInfo::restartsHistory, a new method).
// Takes effect in the next recordFrame.
enum class Invalidate : uint32_t { All, LightsChanged, History };
void invalidate(Module* module, Invalidate what);
// A new render size. Within ModuleDesc::maxWidth × maxHeight (dynamic resolution): the frames from the
// next on render the top-left width × height of the same images. Nothing is allocated or replaced,
// gi::outputs() stays, the histories carry on (reprojected across the change of scale: the G-buffer's
// motion is in the new size's pixels) and so does the hash map; anhpsf's continued paths restart. The
// engine renders its G-buffer into the same top-left rectangle of its views (which may be larger) and
// reads that rectangle of the outputs. Beyond the maximum it becomes the new maximum: every image and
// the hash map start over at it, the old ones are released once the frames using them complete.
Error resize(Module* module, uint32_t width, uint32_t height);
// Records the frame's passes into `cmd`. Fails (recording nothing) only on
// missing G-buffer views or a pre-exposure that is not positive and finite.
Error recordFrame(Module* module, VkCommandBuffer cmd, const FrameInputs& inputs);
// The factor each output holds light in for these settings and pre-exposure:
// preExposure, or 1 where the output holds ratios (aaf_ao) or a picture (the
// composite under a debug view that is not light). Divide by it to get W/(sr·m²).
struct OutputScales {
  float direct = 1.0f, indirect = 1.0f, composite = 1.0f;
};
OutputScales outputScales(const Settings& settings, float preExposure);
// The images the frames write. They change only on a resize beyond the largest size (setSettings and
// dynamic resolution keep them): bind them once per largest size.
Outputs outputs(const Module* module);
// Numbers from the newest recorded frame whose GPU work has completed (with
// ModuleDesc::timestamps off the module cannot tell and trusts that the
// newest recorded frame has).
FrameStats stats(Module* module);
// Numbers of frame `frameIndex` (FrameInputs::frameIndex) once it has
// completed; false while it is in flight or once its slot has been reused.
bool frameStats(Module* module, uint32_t frameIndex, FrameStats& out);

// Programs. Every pass runs a compute program, created the first time
// settings need it (create, setSettings) and kept, so a switch back creates
// nothing. Most drivers compile a program when it is created; Mesa's
// lavapipe compiles it at its first dispatch, on the queue, stalling the
// frames queued behind it. To switch methods without either stall, an engine
// readies the new settings' programs ahead of the switch:
//  - programNames: the programs `settings` run on the module's scene (shader names, recording order);
//  - preparePrograms: creates those not created yet (where the driver compiles at creation, the compile);
//  - programsPrepared: whether setSettings(settings) would create none;
//  - recordProgramWarmup: records into `cmd` a dispatch of no workgroups of each program (or of the
//    one named), bound to 1×1 placeholders the module holds: nothing runs, but a driver that compiles
//    at first dispatch compiles there. Submit it where it holds up no frame (a second queue; on a
//    single-queue device, between frames, accepting that one stall), then call finishProgramWarmup
//    once it has completed, before recording another.
// These four may be called from a thread of the engine's while another
// thread records frames and changes settings: they take a lock of their own,
// which setSettings, setScene and resize take too (recordFrame never waits on
// it). The pipelines go through ModuleDesc::pipelineCache (the engine keeps it
// thread-safe: no VK_PIPELINE_CACHE_CREATE_EXTERNALLY_SYNCHRONIZED_BIT).
std::vector<std::string> programNames(Module* module, const Settings& settings);
Error preparePrograms(Module* module, const Settings& settings);
bool programsPrepared(Module* module, const Settings& settings);
Error recordProgramWarmup(Module* module, const Settings& settings, VkCommandBuffer cmd, std::string_view program = {});
void finishProgramWarmup(Module* module);

}  // namespace gi
