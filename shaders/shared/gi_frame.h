// The GI module's per-frame interface (set 1 of its compute passes): frame
// constants, the engine's G-buffer, the module's outputs and history, and the
// push constants of each pass.
#ifndef GI_FRAME_H
#define GI_FRAME_H
#include "gpu_common.h"
#include "debug_views.h"
#include "gpu_scene.h"

GPU_NAMESPACE_BEGIN

GPU_CONST GI_BINDING_FRAME = 0;          // uniform GiFrameConstants
// The engine's G-buffer, sampled images read with texelFetch in its own
// formats and encodings (gi::GBufferDesc; decoded in gi_frame.glsl).
GPU_CONST GI_BINDING_GB_NORMAL = 1;
GPU_CONST GI_BINDING_GB_ALBEDO = 2;
GPU_CONST GI_BINDING_GB_MATERIAL = 3;
GPU_CONST GI_BINDING_GB_EMISSION = 4;
GPU_CONST GI_BINDING_GB_MOTION = 5;
GPU_CONST GI_BINDING_GB_DEPTH = 6;      // linear view depth, or the hardware depth buffer
// The outputs are in ModuleDesc::outputFormat (rgba16f or rgba32f), so the
// shaders access them without a format qualifier, always through
// giStoreOutput / giLoadOutput (gi_frame.glsl), which apply the pre-exposure.
// Where outputFormat has no alpha (B10G11R11), direct and indirect are the module's own half-float
// working images, and the composite pass copies them into the engine's (GI_BINDING_PACKED_*).
GPU_CONST GI_BINDING_OUT_DIRECT = 7;     // emission + direct light, W/(sr·m²) × pre-exposure
GPU_CONST GI_BINDING_OUT_INDIRECT = 8;   // demodulated indirect light × pre-exposure
GPU_CONST GI_BINDING_OUT_COMPOSITE = 9;  // what the debug view selects (default: the lit image × pre-exposure)
// The radiance histories' set A (B below): the temporal pass's, or where raw (which runs no temporal pass)
// keeps its still-camera running mean (gi_raw_trace.comp's runningMean).
GPU_CONST GI_BINDING_HISTORY_DIRECT_A = 10;   // direct light (rgb), history frames (a)
GPU_CONST GI_BINDING_HISTORY_INDIRECT_A = 11; // demodulated indirect (rgb)
GPU_CONST GI_BINDING_COUNTERS = 12;      // GiCounters, host-visible, one slot per frame in flight
GPU_CONST GI_BINDING_NOISY_INDIRECT = 13;// rgba32f: demodulated indirect before any filter; the hash methods
                                         // alias it to the indirect output (then it holds × noisyScale)
GPU_CONST GI_BINDING_GUIDANCE = 14;      // rgba32f: filter guidance (shared/gi_filters.h contract)
GPU_CONST GI_BINDING_POSITION = 15;      // rgba32f: world position (xyz), view depth (w; 0 = background)
GPU_CONST GI_BINDING_DEBUG = 16;         // rgba32f: a filter's debug output (the filters' temp image)
GPU_CONST GI_BINDING_AAF_PARAMS = 17;    // rgba16f: AAF z_min, z_max, samples, β (metres)
GPU_CONST GI_BINDING_AAF_GLOSSY = 18;    // rgba32f: AAF glossy receivers: Σ, then mean, of lobe·(1 − s)·L (rgb); β_glossy (a)
GPU_CONST GI_BINDING_AAF_GLOSSY_EDGE = 19; // rgba32f: the same for lobe·s·L (Schlick's s); specular = f0·glossy + edge
// Temporal reprojection (gi_temporal.comp): two sets of history, read one, write the other
// (GiTemporalPush::readSet); set A's radiance images are above.
GPU_CONST GI_BINDING_HISTORY_DIRECT_B = 20;   // accumulated direct over the base colour (rgb), history frames (a)
GPU_CONST GI_BINDING_HISTORY_INDIRECT_B = 21; // accumulated demodulated indirect (rgb)
// r32ui: last frame's normal and view depth (temporal.glsl's giPackGuide), which the temporal pass and the
// temporal gradients read; one image, not a set each: this frame's replaces it once they have read it (the
// composite pass, or svgf's variance pass, whose à-trous iterations read it).
GPU_CONST GI_BINDING_HISTORY_GUIDE = 22;
// SVGF (svgf_variance.comp, svgf_atrous.comp): the luminance moments' history, read and written with the
// colour's (sets A and B alternate: GiSvgfPush::writtenSet). Its à-trous iterations hold no images of their own: they ping-pong
// between the outputs and the history set last frame wrote (svgf.glsl), and read their taps' normal and depth
// from the history guide, which the variance pass writes (from the G-buffer) once the temporal pass has read it.
GPU_CONST GI_BINDING_SVGF_STATE_A = 23;     // svgf's luminance variances and frames (gi_frame.glsl's giPackSvgfState)
GPU_CONST GI_BINDING_SVGF_STATE_B = 24;
// Temporal gradients (TemporalSettings::gradients, A-SVGF, Schied et al. 2018): one pixel per
// GI_GRADIENT_TILE² tile traces with the random numbers its reprojected pixel used last frame.
GPU_CONST GI_BINDING_GRADIENT_SAMPLES_A = 25; // rgba32ui: the pixel's first sample, luminance of direct over base colour
GPU_CONST GI_BINDING_GRADIENT_SAMPLES_B = 26; //   and of demodulated indirect as two half floats (x), its random state (y)
                                              //   and with reservoirs its light pick, the light and W's bits (zw)
GPU_CONST GI_BINDING_TEMPORAL_GRADIENT = 27;  // rgba32f, one texel per tile: direct's change and max(then, now) (xy), indirect's (zw)
GPU_CONST GI_BINDING_TEMPORAL_SPREAD = 28;    // rgba32f: this frame's samples around the pixel (3×3): luminance mean
                                              //   and σ of direct over base colour (xy) and of demodulated indirect (zw)
// The hash methods' direct light history (hpsf.temporal), one texel per pixel in 8 bytes
// (temporal.glsl, giPackHistory): the reflected direct light over the base colour, relative to the
// scene's typical radiance, as RGB9E5 (x); view depth / depthScale as a half float, the octahedral
// normal in 2 × 5 bits and the frames of history (to 63) (y). Written by the composite pass, once the
// temporal pass has read every neighbour's texel: one image, not two.
GPU_CONST GI_BINDING_HISTORY_PACKED = 29;
// Reservoir resampling of the primary hits' point and spot lights (ReservoirSettings, gi_reservoirs.comp).
// A and B, rgba32ui, the temporal pass's reservoirs where last frame's are merged, one set written a
// frame (GiReservoirPush::readSet) and read by the next: the chosen light (x; GI_RESERVOIR_EMPTY = none),
// its weight W (y, float bits), the samples behind it M (z's low 16 bits, a half float) and the light's
// target at the pixel (z's high 16, a float's upper 12 bits: giPackConfidence), the pixel's guide (w,
// giPackGuide). Where they are not merged, FRAME_RESERVOIRS instead, rg32ui, written and read within
// the frame: the light (x), and W's upper 20 bits with the target's 12 (y), since M is then the
// candidates' count (0 where the boiling filter dropped the reservoir: W's sign bit) and the guide the
// G-buffer's (giLoadReservoir). The pick,
// rg32ui, the spatial pass's result the tracing passes take (giPrimaryReservoir): the light and its W
// (float bits), 0 where the pixel does not see it. Where a temporal pass keeps half-float histories,
// FRAME_RESERVOIRS and the pick are rg32ui views of the direct and indirect history set that pass
// overwrites later in the frame (the same 8 bytes a texel; frameSet in module.h), not images of their own;
// without such a set (the hash methods) rg32ui views of the half-float direct output, first written by the
// tracing passes, and of the composite, written by the last pass (reservoirHomes in module.h); where
// A and B are merged, the pick alone in the composite.
GPU_CONST GI_BINDING_RESERVOIRS_A = 30;
GPU_CONST GI_BINDING_RESERVOIRS_B = 31;
GPU_CONST GI_BINDING_RESERVOIR_PICK = 32;
// The engine's direct and indirect outputs where ModuleDesc::outputFormat is packed (B10G11R11: no sign,
// no alpha), written by the composite pass alone from OUT_DIRECT and OUT_INDIRECT (GiCompositePush::
// packedOutputs); otherwise the same images as those, and not written.
GPU_CONST GI_BINDING_PACKED_DIRECT = 33;
GPU_CONST GI_BINDING_PACKED_INDIRECT = 34;
GPU_CONST GI_BINDING_FRAME_RESERVOIRS = 35;  // the reservoirs within one frame (with A and B above)
GPU_CONST GI_BINDING_COUNT = 36;
#define GI_GRADIENT_TILE 3u              // pixels per side of a gradient tile (A-SVGF's strata)
#define GI_TRUSTED_HISTORY 4.0           // frames of history from which a pixel's accumulated light speaks for
                                         // itself: SVGF's temporal variance (spatial before), the filter clamp
#define GI_GROUP_SIZE 8u                 // 8×8 threads per group

// Specialisation constants of the module's passes after the scene's
// (SCENE_SPEC_*): how the G-buffer is encoded (gi::GBufferDesc's enums).
#define GI_SPEC_NORMAL_ENCODING 4
#define GI_SPEC_DEPTH_ENCODING 5
#define GI_SPEC_GLOSSY_FLAG 6
#define GI_SPEC_CHECK_BOUNDS 7  // gi::ModuleDesc::checkBounds (bounds.glsl)
#define GI_SPEC_HAS_EMISSION 8  // gi::GBufferDesc::hasEmission: 0, the G-buffer has no emission view (emission 0)
#define GI_SPEC_COUNT 9
GPU_CONST GI_NORMAL_XYZ = 0u;              // rgb = n in [-1,1]
GPU_CONST GI_NORMAL_XYZ_UNORM = 1u;        // rgb = n·0.5 + 0.5
GPU_CONST GI_NORMAL_OCTAHEDRAL = 2u;       // rg = octahedral n in [0,1]
GPU_CONST GI_NORMAL_OCTAHEDRAL_SIGNED = 3u;// rg = octahedral n in [-1,1]
GPU_CONST GI_DEPTH_LINEAR_VIEW_Z = 0u;     // view depth along −Z in metres, 0 = background
GPU_CONST GI_DEPTH_HARDWARE = 1u;          // depth buffer value, far (background) = 1
GPU_CONST GI_DEPTH_HARDWARE_REVERSED = 2u; // depth buffer value, far (background) = 0
GPU_CONST GI_GLOSSY_ALBEDO_ALPHA = 0u;     // albedo.a ≥ 0.5: the pixel has a GGX lobe
GPU_CONST GI_GLOSSY_FROM_MATERIAL = 1u;    // the material image by the scene's rule (materialHasGlossyLobe)

// GiFrameConstants::primaryDirect: how the primary hits' direct light is found.
GPU_CONST GI_PRIMARY_DIRECT_NEE = 0u;         // next-event estimation with the scene's light sampler
GPU_CONST GI_PRIMARY_DIRECT_RESERVOIRS = 1u;  // the point and spot lights from the reservoirs' pick (gi_reservoirs.comp)
GPU_CONST GI_PRIMARY_DIRECT_NONE = 2u;        // none: the engine lights them (Settings::indirectOnly)
GPU_CONST GI_PRIMARY_DIRECT_EMISSIVE = 4u;    // with NEE or RESERVOIRS: the emissive triangles from the reservoirs'
                                              // pick too (a bit: NEE | EMISSIVE keeps NEE's exact punctual sum)
GPU_CONST GI_PRIMARY_DIRECT_SKY = 8u;         // with RESERVOIRS or EMISSIVE: a sky map's share too, weighed
                                              // against BSDF sampling (lights.glsl's giReservoirsSampleSky)

struct GiFrameConstants {
  GpuCamera camera;
  GpuCamera previousCamera;  // its imageSize: last frame's render size (dynamic resolution: what its histories cover)
  uvec2 size;        // pixels
  uint frameIndex;
  float depthScale;  // metres: view depth is divided by it for the filters' guidance (the scene extent, fixed)
  float outputScale; // radiance → output units: FrameInputs::preExposure (1 for aaf_ao, whose outputs are ratios)
  float outputMax;   // largest finite value of the output format (65504 for half floats): stores clamp to it
  float noisyScale;  // outputScale when the noisy indirect aliases the indirect output; else as historyScale
  float noisyMax;    // outputMax when it aliases the indirect output; else as historyMax
  float historyScale;// radiance → the radiance histories' units: 1 / the scene's typical radiance where they are
                     // half floats (temporal reprojection), 1 where they are single floats (raw's running mean)
  float historyMax;  // their format's largest finite value (65504 or the largest float): stores clamp to it
  uint primaryDirect;  // GI_PRIMARY_DIRECT_*: how the primary hits' direct light is found
  uint lightSampler; // LIGHT_SAMPLER_* of NEE in the module's passes (LightSettings::sampler, or the scene's)
  mat4 viewFromClip; // inverse of the camera's projection: hardware depth → view depth
  vec2 motionScale;  // the G-buffer's stored motion → pixels: GBufferDesc::motionScale × its units' pixels
  vec2 motionOffset; // pixels added after: the cameras' jitter difference where the engine's motion leaves it out
  float compositeMax; // largest finite value of the composite's format (ModuleDesc::compositeFormat)
  uint svgfWideState; // 1: svgf's state image holds its variances and frames as single floats (with single-float
                      // histories); 0: packed in one word (gi_frame.glsl's giPackSvgfState)
  float skyVisibility; // GI_PRIMARY_DIRECT_SKY: the share of recent frames' sky picks that saw the sky, in
                       // [GI_SKY_VISIBILITY_MIN, 1]; the sky's share of the reservoirs' candidates and its target
                       // are scaled by it (lights.glsl's giReservoirSkyShare, gi_reservoirs.comp's giReservoirTarget)
};
GPU_ASSERT_SIZE(GiFrameConstants, 748);
// The least GiFrameConstants::skyVisibility: an occluded sky keeps a few candidates, which find it again
// when the camera walks out under it.
#define GI_SKY_VISIBILITY_MIN (1.0f / 256.0f)

// The temporal pass's history lengths (frames behind a pixel, this one included) are counted in this
// many bins, the last holding every length from GI_HISTORY_BINS − 1 up: FrameStats::accumulatedFrames is
// the median's bin.
GPU_CONST GI_HISTORY_BINS = 64u;
// Only every GI_HISTORY_ROW_STEP-th row is counted: the median of a sample, at one atomic per subgroup
// where its lanes agree (a still camera's), so the count costs well under a millisecond at 1080p.
GPU_CONST GI_HISTORY_ROW_STEP = 8u;

struct GiCounters {
  uint raysTraced;        // added to by every tracing pass
  uint requestedSamples;  // AAF pass 1: Σ n(μ) over pixels
  uint tracedSamples;     // AAF pass 2: Σ samples actually traced
  uint sanitized;         // non-finite G-buffer pixels and path samples dropped at the module boundary
  uint coveredPixels;     // AAF pass 1: pixels with geometry (each takes the 16 initial samples)
  uint boundsViolations;  // ModuleDesc::checkBounds: image coordinates outside their image (bounds.glsl)
  uint skyPicksTested;    // reservoir spatial pass: pixels whose pick is a sky direction, its shadow ray traced
  uint skyPicksVisible;   // of those, the rays that left the scene (GiFrameConstants::skyVisibility)
  uint historyFrames[GI_HISTORY_BINS];  // gi_temporal.comp: covered pixels of the counted rows by history length
};
GPU_ASSERT_SIZE(GiCounters, 32 + 4 * 64);

// The reservoir passes (gi_reservoirs.comp): GI_RESERVOIR_TEMPORAL draws the candidates and merges last
// frame's reservoir through the motion vectors (last frame's set → this frame's); GI_RESERVOIR_SPATIAL
// merges neighbours' and tests the survivor's visibility (this frame's set → the pick); GI_RESERVOIR_PICK,
// where no neighbours are merged, is the temporal pass and the survivor's shadow ray in one.
GPU_CONST GI_RESERVOIR_TEMPORAL = 0u;
GPU_CONST GI_RESERVOIR_SPATIAL = 1u;
GPU_CONST GI_RESERVOIR_PICK = 2u;
struct GiReservoirPush {
  uint mode;            // GI_RESERVOIR_*
  uint seed;
  uint candidates;      // lights drawn per pixel (ReservoirSettings::candidates)
  uint temporal;        // 1: merge last frame's reservoir (0 on the first frame of a history)
  uint neighbours;      // spatial: reservoirs merged from around the pixel
  float radius;         // spatial: pixels
  float maxHistory;     // a merged reservoir counts at most this many times `candidates` samples
  uint unbiased;        // spatial: 1/Z weights (neighbours whose surface the light can reach), else 1/M
  float depthTolerance; // the reprojection and neighbour tests (TemporalSettings)
  float cosNormalLimit;
  uint readSet;         // 0: last frame's temporal reservoirs are in A, this frame's go to B; 1: the reverse
  uint pairwise;        // spatial, with `unbiased`: pairwise MIS against the pixel's own reservoir, else the
                        // balance heuristic over every surface
  float boilingFilter;  // temporal: a reservoir whose estimate is above this many times its group's others'
                        // mean is dropped (0: off)
  uint frameSet;        // 1: last frame's reservoirs are not merged: this frame's are FRAME_RESERVOIRS
                        // (readSet unused), 0: sets A and B
  uint groupCandidates;   // temporal, [0, 8]: the emissive triangles' candidates come from the 8×8 group's
                          // shared draws, this many by each invocation (ReservoirSettings::groupCandidates),
                          // where they are walked down their tree; 0: each pixel draws its own
  float groupPowerShare;  // (0, 1]: the share of those draws picked by power
};
GPU_ASSERT_SIZE(GiReservoirPush, 64);

struct GiRawPush {
  uint seed;
  uint samplesPerPixel;       // ≥ 1
  uint maxBounces;            // ≥ 1
  uint russianRouletteStart;
  uint historyLength;         // frames already in the history images; 0 = start over
  uint maxHistory;            // cap on the running mean's weight
  uint accumulate;            // 1 = blend with history, 0 = this frame only
  uint gradients;             // 1 (TemporalSettings::gradients): keep each pixel's first sample for the
                              // next frame's gradients (gi_temporal_gradient.comp reads this struct too)
  uint readSet;               // the temporal pass's this frame: 0 = last frame wrote set A (this one writes B)
  float depthTolerance;       // gradients: the reprojection tests of GiTemporalPush
  float cosNormalLimit;
};
GPU_ASSERT_SIZE(GiRawPush, 44);

// Temporal reprojection of a screen-space method's noisy direct and indirect
// light (SVGF's temporal half): last frame's history is reprojected through
// the motion vectors, bilinearly, each tap kept only where its depth and
// normal agree; the pixel then blends in this frame by 1/(frames + 1), at
// least minBlend.
struct GiTemporalPush {
  uint readSet;         // 0: read set A, write set B; 1: the other way round
  uint reset;           // 1: no history (first frame, new size, settings or invalidate)
  float minBlend;       // (0, 1]: the smallest weight of the new frame (caps the history at about 1/minBlend frames)
  float depthTolerance; // relative view-depth difference a history tap may have
  float cosNormalLimit; // cosine of the largest normal change a history tap may have
  uint directOnly;      // 1 (the hash methods): only the direct light is reprojected (their map filters the
                        // indirect in time); its history is GI_BINDING_HISTORY_PACKED, and this frame's goes
                        // out through the direct output (frames in its alpha) for the composite to store
  uint direct;          // 1: accumulate the direct light too; 0: it is exact every frame (punctual lights only)
  uint moments;         // 1 (svgf): also accumulate the luminance moments of direct and indirect light
  float momentsMinBlend;// (0, 1]: their smallest weight of the new frame
  uint gradients;       // 1: where the tiles' temporal gradients say the light changed, the new frame weighs more
  uint indirectOutput;  // 1: the accumulated indirect replaces the indirect output (the filters read it); 0 (the
                        // hash methods' filter clamp): it goes to the noisy image only, the map's light stays
  float historyClamp;   // γ_h: history held within γ_h σ of this frame's 3×3 samples (the spread image); 0 = off
  float historyScale;   // packed history: radiance × this (1 / the scene's typical radiance) is stored
  uint noisyOutput;     // 1: the accumulated indirect also replaces the noisy image, which the filter or the
                        // filter clamp reads next; 0 where nothing does (MethodPlan::filtersReadHistory: the
                        // filters read the indirect history, and the noisy image is the output they overwrite)
};
GPU_ASSERT_SIZE(GiTemporalPush, 56);

// svgf_variance.comp and svgf_atrous.comp.
struct GiSvgfPush {
  uint writtenSet;      // the history set the temporal pass wrote this frame: 0 = A, 1 = B
  uint iteration;       // à-trous: taps 2^iteration pixels apart
  float sigmaLuminance; // σ_l: luminance stop in standard deviations
  float sigmaNormal;    // σ_n: exponent on max(0, n·n')
  float sigmaDepth;     // σ_z: depth stop in local depth gradients
  uint iterations;      // à-trous iterations this frame (svgf.glsl's ping-pong follows from it)
  uint direct;          // 1: the direct light is filtered too (area lights); 0: left as the trace wrote it
  uint debug;           // 1: the variance estimate also goes to the debug image (the svgf variance view)
};
GPU_ASSERT_SIZE(GiSvgfPush, 32);

GPU_CONST GI_CLAMP_INDIRECT = 1;      // the filter clamp holds the indirect output
GPU_CONST GI_CLAMP_DIRECT = 2;        // and the direct output (svgf with filterDirect)
GPU_CONST GI_CLAMP_FROM_MOMENTS = 4;  // against svgf's first luminance moments (its colour history holds its
                                      // filter's feedback); otherwise against the noisy image (indirect only)
GPU_CONST GI_CLAMP_FILTER_VERTICES = 8;  // only where the noisy image's alpha marks a filter vertex (sspsf, the hash
                                         // methods: the other pixels keep their own samples, untouched)
GPU_CONST GI_CLAMP_FROM_HISTORY = 16;  // the noisy image the filter read is the indirect history written this
                                       // frame (MethodPlan::filtersReadHistory): spread and flag from there

struct GiCompositePush {
  uint debugView;      // GI_DEBUG_*
  uint ambientOcclusion;  // 1: the indirect image holds occlusion; show AO = 1 − occlusion
  float sceneExtent;   // metres, scales the AAF distance views
  float pixelScale;    // world pixel size per metre of depth, for the AAF filter-width view
  uint aafSpecular;    // 1: add AAF's filtered specular term (f0·glossy + edge) on glossy receivers
  uint radiance;       // 1: the view is light and carries the pre-exposure; 0: a [0,1] picture stored as is
  uint temporalWritten;// the history set the temporal pass wrote this frame: 0 = A, 1 = B, 2 = it did not run
  uint gradients;      // 1: the trace wrote this frame's temporal gradients
  float filterClamp;   // γ (TemporalSettings::filterClamp): the filtered light within γ local σ of the accumulated; 0 = off
  uint clampLight;     // GI_CLAMP_*: what the filter changed, and what it is held against
  uint packedHistory;  // 1: store the packed direct history (GiTemporalPush::directOnly), frames from
                       // the direct output's alpha, which goes back to 1
  float historyScale;  // GiTemporalPush::historyScale
  uint svgfFrames;     // 1: the frames are in svgf's state image of the set written (gi_frame.glsl's giLoadSvgfFrames)
  uint packedOutputs;  // 1: copy the direct and indirect light into GI_BINDING_PACKED_* (clamped to [0, packedMax])
  float packedMax;     // the packed format's largest finite value
  uint writesGuide;    // 1: store this frame's history guide (GI_BINDING_HISTORY_GUIDE), which the temporal pass
                       // has read; 0: no temporal pass reads one (or svgf's variance pass stored it)
};

struct GiGuidancePush {
  uint positions;  // 1: the position image is held (MethodPlan::filterPositions) and written too
};
GPU_ASSERT_SIZE(GiGuidancePush, 4);

struct GiSupersamplePush {
  uint seed;
  uint supersamples;  // extra eye rays per pixel
};
GPU_ASSERT_SIZE(GiSupersamplePush, 8);
GPU_ASSERT_SIZE(GiCompositePush, 64);

GPU_NAMESPACE_END
#endif
