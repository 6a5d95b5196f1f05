// Settings of the GI module: one struct per method, every field defaulted,
// with its unit and range. gi::validate (gi.h) names any value outside them.
#pragma once
#include <cstdint>
#include <string>

#include "shared/debug_views.h"

namespace gi {

enum class Method : uint32_t {
  Raw = 0,    // unfiltered paths (optionally averaged over frames)
  Gif,        // guided image filter on demodulated indirect (Bauszat et al. 2011)
  Bilateral,  // cross-bilateral baseline
  Atrous,     // edge-avoiding à-trous baseline (Dammertz et al. 2010)
  Aaf,        // axis-aligned filtering with adaptive sampling (Mehta et al. 2013)
  AafAo,      // the same machinery for ambient occlusion (reflectors radiate 1): the indirect
              // output holds occlusion, the composite AO = 1 − occlusion, both in [0,1]
  Sspsf,      // screen-space path filtering (Meijer 2019 §4.1)
  Hpsf,       // hashed path space filtering on a persistent world-space hash map (§4.2)
  Nhpsf,      // HPSF at every diffuse vertex of a path; the last vertex reads the map (§4.3)
  Anhpsf,     // nHPSF amortised: each pixel extends one long path by a segment per frame (§4.4)
  Svgf,       // spatiotemporal variance-guided filtering (Schied et al. 2017): the production baseline
};
inline constexpr uint32_t kMethodCount = 11;
// "raw", "gif", "bilateral", "atrous", "aaf", "aaf_ao", "sspsf", "hpsf", "nhpsf", "anhpsf", "svgf"
const char* methodName(Method method);
bool methodFromName(const std::string& name, Method& out);  // false for unknown names

enum class DebugView : uint32_t {
  None = gpu::GI_DEBUG_NONE,                         // composite = direct + diffuse albedo × indirect
  Direct = gpu::GI_DEBUG_DIRECT,                     // direct light only (emission + first reflection)
  Indirect = gpu::GI_DEBUG_INDIRECT,                 // demodulated indirect light
  Albedo = gpu::GI_DEBUG_ALBEDO,                     // G-buffer base colour
  Normal = gpu::GI_DEBUG_NORMAL,                     // G-buffer normal, mapped to [0,1]
  Guidance = gpu::GI_DEBUG_GUIDANCE,                 // filter guidance: normal (rgb) as the guided filter sees it
  GuidanceDepth = gpu::GI_DEBUG_GUIDANCE_DEPTH,      // filter guidance: depth channel
  FilterInOut = gpu::GI_DEBUG_FILTER_IN_OUT,         // left half: noisy indirect; right half: filtered
  GifCoefficients = gpu::GI_DEBUG_GIF_COEFFICIENTS,  // guided filter: |a| (r), |b| (g) per pixel
  AafZMin = gpu::GI_DEBUG_AAF_ZMIN,                  // AAF: nearest reflector distance / scene extent
  AafZMax = gpu::GI_DEBUG_AAF_ZMAX,                  // AAF: farthest reflector distance / scene extent
  AafSamples = gpu::GI_DEBUG_AAF_SAMPLES,            // AAF: samples per pixel / 100
  AafFilterWidth = gpu::GI_DEBUG_AAF_FILTER_WIDTH,   // AAF: filter σ in pixels / 32
  HashCells = gpu::GI_DEBUG_HASH_CELLS,              // HPSF: each pixel's cell, coloured by its key
  HashLod = gpu::GI_DEBUG_HASH_LOD,                  // HPSF: the cell's level of detail
  HashSamples = gpu::GI_DEBUG_HASH_SAMPLES,          // HPSF: samples behind the cell's mean / 100
  HashFound = gpu::GI_DEBUG_HASH_FOUND,  // HPSF: green = cell used, yellow = too few samples, red = no cell (fallback)
  HashOccupancy = gpu::
      GI_DEBUG_HASH_OCCUPANCY,  // HPSF: how full the probe window around the pixel's cell is, green (empty) → red (full; red also = no cell)
  ContinuationDepth =
      gpu::GI_DEBUG_CONTINUATION_DEPTH,  // A-nHPSF: depth of the pixel's continued path / the maximum depth
  TemporalHistory = gpu::
      GI_DEBUG_TEMPORAL_HISTORY,  // temporal reprojection: frames of history behind the pixel / 32 (1/32: it started over)
  SvgfVariance = gpu::
      GI_DEBUG_SVGF_VARIANCE,  // svgf: the luminance variance estimate of direct (r) and indirect (g) light, history frames / 32 (b)
  TemporalGradient = gpu::
      GI_DEBUG_TEMPORAL_GRADIENT,  // temporal gradients: how much of the history the pixel drops, direct (r) and indirect (g)
};
inline constexpr uint32_t kDebugViewCount = uint32_t(DebugView::TemporalGradient) + 1;  // keep after the last view

struct RawSettings {
  uint32_t samplesPerPixel = 1;          // paths per pixel per frame, [1, 64]
  bool temporalAccumulation = false;     // average frames while the camera and settings stay unchanged
  bool temporalReprojection = false;     // blend in last frame's reprojected light (TemporalSettings); off: raw stays
                                         // the per-frame Monte Carlo baseline
  uint32_t maxAccumulatedFrames = 4096;  // history cap, [1, 1<<20]; older frames fade out past it
};

struct GifSettings {
  uint32_t samplesPerPixel = 1;      // indirect paths per guide ray, [1, 64]
  uint32_t radius = 24;              // window radius in pixels, [1, 128]; cost does not depend on it
  uint32_t subsample = 4;            // window statistics at 1/s resolution per axis, [1, 8]: their memory ÷ s²
                                     // (4: 2–4% more error than 1, 249 MB less at 1080p; docs/RESULTS.md)
  float epsilonNormal = 0.01f;       // ridge term for normal channels, [0, 1e6] (guidance in [0,1])
  float epsilonDepth = 0.02f;        // ridge term for the depth channel, [0, 1e6]
  uint32_t guidanceDimensions = 4;   // 1 = grey normal, 3 = normal, 4 = normal + depth
  uint32_t supersamples = 0;         // extra eye rays per pixel with geometry-aware lookup, [0, 16]
  bool temporalReprojection = true;  // blend in last frame's reprojected light before filtering (TemporalSettings)
};

struct BilateralSettings {
  uint32_t samplesPerPixel = 1;      // [1, 64]
  uint32_t radius = 16;              // pixels, [1, 64]; cost grows with radius²
  float sigmaSpatial = 8.0f;         // pixels, (0, 1e4]
  float sigmaNormal = 0.1f;          // on the difference of normal·0.5+0.5, (0, 1e4]
  float sigmaDepth = 0.05f;          // on the depth difference relative to the centre's depth, (0, 1e4]
  bool temporalReprojection = true;  // blend in last frame's reprojected light before filtering (TemporalSettings)
};

struct AtrousSettings {
  uint32_t samplesPerPixel = 1;      // [1, 64]
  uint32_t iterations = 5;           // [1, 8]: taps up to 2^(iterations+1) pixels away
  float sigmaColor = 0.5f;           // colour stop in demodulated radiance, halved per iteration, (0, 1e6]
  float sigmaNormal = 0.1f;          // on the difference of normal·0.5+0.5, (0, 1e4]
  float sigmaPosition = 0.05f;       // world distance as a fraction of the centre's view depth, (0, 1e4]
  bool temporalReprojection = true;  // blend in last frame's reprojected light before filtering (TemporalSettings)
};

struct AafSettings {
  float mu = 0.9f;                   // filter scale μ, (0, 16]: > 1 narrows filters and raises sample counts
  float alpha = 0.3f;                // pixel-space band limit α, (0, 1]
  float normalLimitDegrees = 10.0f;  // neighbours whose normals differ more are not filtered in, [0, 180]
  uint32_t uniformSamples = 0;       // 0 = adaptive (eq. 21); N ≥ 16 = N samples in every pixel (Fig. 10's
                                     // "filtered uniform" curve), [0, 1024]
  uint32_t maxRadius = 0;            // pixels, [0, 1024]: the screen-space Gaussian reaches 3σ (the paper), cut
                                     // here when not 0 (cheaper; the result then depends on the resolution)
};

struct SspsfSettings {
  uint32_t samplesPerPixel = 1;      // [1, 64]
  uint32_t window = 9;               // odd window side in pixels, [1, 31]
  float filterWidth = 16.0f;         // pixels, [0.5, 256]: the position kernel matches the HPSF cell of this width
  float normalLimitDegrees = 25.0f;  // [0, 180]
  bool temporalReprojection = true;  // blend in last frame's reprojected light before filtering (TemporalSettings)
};

// SVGF (Schied et al. 2017) as published: temporal accumulation of the
// demodulated direct and indirect light with their luminance moments
// (TemporalSettings' reprojection tests), per-pixel variance from the moments
// (a 7×7 spatial estimate while a pixel has fewer than 4 frames of history),
// then à-trous iterations with the variance-guided luminance edge stop and
// normal and depth stops; the first iteration's result is fed back as the
// history. Direct light is filtered where it has noise (area lights: emissive
// triangles, a sky); punctual lights' direct light is exact and left alone.
struct SvgfSettings {
  uint32_t samplesPerPixel = 1;  // [1, 64]
  float alpha = 0.2f;            // (0, 1]: the smallest weight of the new frame's colour (the paper's α)
  float momentsAlpha = 0.2f;     // (0, 1]: the same for the luminance moments (the paper's α for moments)
  uint32_t iterations = 5;       // [0, 8]: à-trous iterations (taps up to 2^(iterations+1) pixels away); 0 =
                                 // accumulation only
  float sigmaLuminance = 4.0f;   // (0, 1e4]: σ_l, the luminance stop in standard deviations
  float sigmaNormal = 128.0f;    // (0, 1e4]: σ_n, the exponent on max(0, n·n')
  float sigmaDepth = 1.0f;       // (0, 1e4]: σ_z, the depth stop in units of the local depth gradient
  bool filterDirect = true;      // filter the area lights' direct light too (the paper); off: accumulated only
};

// Temporal reprojection, for the screen-space methods that turn it on
// (<method>.temporalReprojection: raw without raw.accumulate, gif, bilateral,
// atrous, sspsf): last frame's direct and indirect light, reprojected through
// the G-buffer's motion vectors, is blended into this frame's before the
// method's filter (SVGF's temporal accumulation). Disoccluded pixels (depth or
// normal disagree) start over. The filter's result is then held near the
// accumulated light (filterClamp). These are its tunables, shared by the methods.
struct TemporalSettings {
  float minBlend = 0.1f;        // (0, 1]: the smallest weight of the new frame; history ≈ 2/minBlend − 1 frames
  float depthTolerance = 0.1f;  // (0, 10]: relative view-depth difference a history tap may have
  float normalLimitDegrees = 25.0f;  // [0, 180]: the largest normal change a history tap may have
  float filterClamp = 0.5f;          // [0, 10]: γ, the filtered light may lie at most γ standard deviations from
                                     // the mean of the accumulated light around the pixel (3×3, luminance); 0 = off.
                                     // As the history grows the filter can no longer leave a bias its input
                                     // disproves (RESULTS: 0.5 removes the speckles; 1 keeps a few of svgf's)
  float historyClamp = 0.0f;         // [0, 10]: γ_h, the reprojected history may lie at most γ_h standard
                                     // deviations from the mean of this frame's samples around the pixel (3×3,
                                     // luminance) before it is blended in (TAA's clamp, Salvi 2016); 0 = off.
                                     // Off by default: measured over the walk, the demo's scene and a moved
                                     // light (docs/RESULTS.md, "The history clamp")
  bool gradients = false;            // A-SVGF's temporal gradients (Schied et al. 2018): one pixel per 3×3 tile
                                     // re-traces last frame's random numbers; where its light changed, the
                                     // new frame weighs more. For the methods whose paths start in raw's
                                     // trace (not the hash methods, whose map has its sentinel rays)
};

enum class EvictionPolicy : uint32_t {
  Strict = 0,  // Meijer: two tables swapped every frame; a cell touched this frame carries its whole history
               // over, one not touched is gone
  Aging,       // SHaRC-style: history capped at historyFrames, evicted after staleFrames untouched
};

// The travel that sets the level of detail of nhpsf/anhpsf's vertices after the first
// (the primary vertex's is always its L∞ distance from the camera, Meijer Alg. 3).
enum class SecondaryLod : uint32_t {
  Segment = 0,  // Meijer Alg. 1/3 as written: the L∞ length of the segment that reached the vertex plus the
                // unfiltered travel before it (through glossy vertices)
  Path,         // the L∞ travel of the whole path from the camera
  Camera,       // the vertex's L∞ distance from the camera, as if it were primary
};

// The largest hash map, cells (HpsfSettings::capacity's range; anhpsf's continued paths keep the index hash
// of the cell they feed to this many values).
inline constexpr uint32_t kMaxHashCapacity = 1u << 21;

struct HpsfSettings {
  uint32_t samplesPerPixel = 1;  // [1, 64]
  uint32_t capacity = 0;         // cells, a power of two in [2^10, kMaxHashCapacity]; 0 = gi::hashCapacity's default
  uint32_t probeWindow = 16;     // linear-probing limit in slots, [1, 64]
  float filterWidth = 16.0f;  // pixels, [0.5, 256]: cell size = width × pixel footprint × distance, to a power of two
  float jitter = 0.3f;        // tangent-plane jitter, ± cells (Meijer Alg. 3's δ ∈ [−1, 1]³), [0, 2]; 0 = off.
                              // Meijer shows 0.6; 0.3 has 10–33% less indirect error on every scene (RESULTS)
  uint32_t normalBits = 2;    // normal bins: 2^b in all (Meijer §4.2.2, his 2), [0, 6]; 0 = normals ignored
  float normalJitter = 0.0f;  // normal jitter, ± bins (Meijer Figs. 11c, 14c), [0, 2]; 0 = off
  bool stochasticLod = false;  // pick between the two nearest levels at random (hides LOD seams, costs error)
  float clampSigma = 10.0f;    // clamp samples above mean + k·σ of the cell, [0 = off, 100]; RESULTS: bias per k
  EvictionPolicy eviction = EvictionPolicy::Aging;
  uint32_t historyFrames = 20;      // aging: frames of history kept, [2, 10000]
  uint32_t historySamples = 8;      // aging, nhpsf/anhpsf: what a cell passes on to the vertices before it is its
                                    // mean over this many samples (a cell that gets n a frame: historySamples / n
                                    // frames), so the deep bounces the map builds frame by frame arrive sooner;
                                    // the pixel still shows the historyFrames mean. [0 = the same mean, 1e6]
  uint32_t staleFrames = 60;        // aging: frames untouched before eviction, [1, 100000]
  uint32_t minSamples = 1;          // fewer samples in the cell: the pixel keeps its own, [1, 1e6]
  uint32_t validationInterval = 4;  // aging: every N frames each cell re-traces its sentinel ray (stored when the
                                    // cell was made); if the answer changed by more than the cell's noise, the
                                    // history is cut to match (docs/RESULTS.md, "stale radiance"). A static
                                    // scene answers bit-exactly the same. 0 = off, [0, 1000]
  bool deferredClaims = false;      // aging: a key missing from the map asks for its first free slot and the
                                    // largest key asking gets it after the frame's inserts, so which samples a
                                    // full map turns away follows from the keys, not from the order the GPU ran
                                    // them in: the same frames give the same image. A new cell's first samples
                                    // come a frame later. Strict eviction claims at once.
  // nhpsf and anhpsf (hpsf, nhpsf and anhpsf share the map and the settings above):
  uint32_t pathDepth = 3;          // nhpsf: path segments per pixel and frame, each vertex filtered, [1, 16]
  uint32_t continuationDepth = 4;  // anhpsf: the longest path continued over frames, in segments, [2, 16]
  SecondaryLod secondaryLod = SecondaryLod::Camera;  // nhpsf/anhpsf: the travel behind later vertices' cells
                                                     // (Meijer's Segment makes them small: noisier, the map fills)
  float secondaryWidthScale = 1.0f;                  // cells after the first: at least this much wider, [1, 16]
  bool temporalDirect = true;     // blend in last frame's direct light, reprojected (TemporalSettings): the map
                                  // holds the indirect light in world space, the direct light has no cache, and
                                  // without this it is one frame's samples (speckles at 1 spp). Runs only where
                                  // the scene has area lights (emissive, sky). Its history is one packed image,
                                  // 8 bytes a pixel (RGB9E5 light, half depth, 2 × 5-bit normal, frames to 63)
  bool temporalIndirect = false;  // with temporalDirect and temporal.filterClamp: the pixels' own indirect
                                  // samples are accumulated too and the map's light is held within γσ of them
                                  // (RESULTS: 0.89–0.94× the error under motion). Off by default: it takes four
                                  // full-size fp32 history images more, past issue 17's 150 MB for hpsf at 1080p
};

// Reservoir resampling of the primary hits' point and spot lights and emissive triangles (ReSTIR DI,
// Bitterli et al. 2020), for every method (shaders/module/gi_reservoirs.comp): candidates from the scene's
// light samplers resampled by their unshadowed light, last frame's reservoir merged through the motion
// vectors, the survivor's visibility tested, neighbours merged; the pixel's primary hit then takes the
// reservoir's light with one shadow ray instead of one a subtree of the light tree's cut and one towards a
// triangle. The point and spot lights are resampled where NEE picks among them (gi::picksPunctualLights,
// under the sampler in use; with no more than the cut has subtrees NEE's sum is exact), the emissive
// triangles where there are more than `emissiveMin` (a triangle's sample is a fixed
// point of it, which the neighbours and the next frame reuse; the primary hit's BSDF-sampled rays then count
// no emitter, and its area-light ray goes to the sky alone); with neither nothing runs. Where they run, a
// sky map is resampled too (`sky`). Vertices after the primary hit keep the light samplers.
struct ReservoirSettings {
  bool enabled = true;           // on: measured better for raw, svgf and hpsf from 64 lights on (RESULTS, "Reservoirs")
  uint32_t candidates = 8;       // [1, 64]: lights drawn per pixel and frame (raw's: rawCandidates)
  bool temporal = true;          // merge last frame's reservoir (TemporalSettings' depth and normal tests), for the
                                 // methods without a temporal pass (raw, aaf): one that averages the direct light
                                 // over frames averages more noise away from fresh picks (docs/RESULTS.md)
  uint32_t neighbours = 5;       // [0, 8]: reservoirs merged from around the pixel for its pick (0 = no spatial
                                 // reuse: one pass draws and picks; raw's: rawNeighbours); the next frame
                                 // reuses the pixel's own. More lower every method's error from 64 lights on
                                 // and cost the spatial pass more: 5 is where hpsf meets 1.5x its 4-light
                                 // error at 1024 lights (docs/RESULTS.md, "Reservoirs")
  uint32_t rawCandidates = 4;    // [1, 64]: `candidates` for raw where its reservoirs merge over frames (`temporal`,
                                 // raw.temporal off) and each frame is seen alone (raw.accumulate off): the
                                 // merge carries up to maxHistory times them, so fewer a frame suffice
  uint32_t rawNeighbours = 0;    // [0, 8]: `neighbours` for raw where they merge. Against 8 and 5, 4 and 0 cost
                                 // raw 0.40x the reservoir passes for 1.03x the error at 1024 panels and 0.50x
                                 // for 0.98x at 1024 point lights; aaf, the other method with the merge, kept
                                 // its time and had 1.17x the error, so it keeps `candidates` and `neighbours`
                                 // (docs/RESULTS.md, "The reservoirs' budget where the merge runs"). Where
                                 // frames are averaged the fewer, unshared picks correlate them, and
                                 // `candidates` and `neighbours` serve: raw accumulating 10 frames there had
                                 // 1.38x the error with 4 and 0; and while a sky map is in the reservoirs
                                 // (`sky`), whose sun stop 70 measured with 8 and 5
  float radius = 4.0f;           // pixels, [1, 64]: the disc the neighbours come from
  float maxHistory = 20.0f;      // [1, 1000]: last frame's reservoir counts at most this many times the frame's
                                 // candidates
  float skyMaxHistory = 4.0f;    // [1, 1000]: maxHistory while a sky map is in the reservoirs (`sky`, its measured
                                 // visibility above its least): the temporal reuse correlates a pixel's frames,
                                 // which the sun's few bright samples make costly where it is hidden from part
                                 // of the view (docs/RESULTS.md, "The sky in the reservoirs")
  uint32_t emissiveMin = 16;     // [0, 2^22]: the emissive triangles are resampled where a scene has more than
                                 // this many: on the light hall 4 panels' 8 gained nothing for the two passes
                                 // (error 0.91–0.99×, time 1.5–2.1× at 160×90 on lavapipe), 16 panels' 32 did
                                 // (0.44–0.81×; docs/RESULTS.md, "Emissive triangles in the reservoirs")
  bool unbiased = true;          // spatial weights: the balance heuristic over the reservoirs' surfaces' targets
                                 // (no fireflies where a light is bright here and dim where it was drawn);
                                 // off, the biased 1/M. Neither traces a shadow ray per neighbour
  bool pairwise = true;          // with `unbiased`: pairwise MIS (each neighbour's sample weighed against the
                                 // pixel's own surface alone: 2N+1 target evaluations for N neighbours) instead
                                 // of the balance heuristic over every surface ((N+1)^2). Measured: the same
                                 // error for 0.84-0.94x the frame where the reservoirs hold emissive triangles,
                                 // 1.00-1.07x the error for 0.90-0.99x the frame with point lights
                                 // (docs/RESULTS.md, "Pairwise MIS")
  float boilingFilter = 40.0f;   // [0, 1000], 0 = off: a temporal reservoir whose estimate of the pixel's
                                 // unshadowed light is above this many times the mean of its 8x8 group's
                                 // others is dropped, not kept nor reused (RTXDI's boiling filter: a sample
                                 // whose weight is an outlier would otherwise be kept and spread for frames;
                                 // biased: it darkens where it drops)
  uint32_t groupCandidates = 0;  // [0, 8]: the emissive triangles' candidates drawn for each 8x8 group of pixels,
                                 // this many by each of its 64 pixels (walks down their tree from the surface
                                 // nearest the group's centre, mixed with picks by power so that no triangle a
                                 // pixel sees has density 0), each pixel resampling `candidates` of the group's
                                 // by its own target: this many walks a pixel, not `candidates`. Unbiased (each
                                 // draw's density is the group's mixture, the same for every pixel), but the
                                 // pixels of a group share their draws, and their noise (docs/RESULTS.md, "The
                                 // group's candidates"). 0: each pixel draws its own
  float groupPowerShare = 0.25f;  // (0, 1]: with groupCandidates, the share of the group's candidates drawn by
                                  // power (the rest down the tree at the group's surface)
  bool sky = false;               // where the reservoirs run for the lights above, a sky map's light too: a share of
                                  // the candidates (its irradiance against the trees' importance) are directions
                                  // from the map, resampled by their light weighed against BSDF sampling, whose
                                  // rays from the primary hit take the rest (no share of its area-light ray; a
                                  // constant sky has no light pdf: BSDF sampling finds it, as without). The sky's
                                  // share and target are scaled by its measured visibility (the share of recent
                                  // sky picks whose shadow ray saw it, FrameStats::skyPicks), so a sky the scene
                                  // hides everywhere is soon left alone, and a sky direction whose shadow ray
                                  // failed at a pixel leaves its reservoir (visibility reuse: biased, under 1%),
                                  // and raw's and aaf's merge keeps skyMaxHistory. Off by default: raw's error
                                  // falls wherever the sky is seen, but svgf's and hpsf's grow by 11-12% where
                                  // the sun shares the view with lamps as bright (one pick and shadow ray for
                                  // both, not one each; docs/RESULTS.md, "The sky in the reservoirs")
};

// The light sampler of next-event estimation in the module's passes (shaders/module/lights.glsl): the scene's
// (gi::SceneCreateDesc::lightSampler, which the reference path tracer uses too) or one of the three, over
// the same tables (the scene always builds the power table and the tree with its cut).
enum class LightSampling : uint32_t {
  Scene = 0,  // SceneCreateDesc::lightSampler
  All,        // a shadow ray to every punctual light at every vertex (exact; cost grows with the count)
  Power,      // one light a vertex, picked by its power
  Tree,       // every directional light and one light from each subtree of the tree's cut; the emissive
              // triangle down their own tree
};
struct LightSettings {
  LightSampling sampler = LightSampling::Scene;
};

struct Settings {
  Method method = Method::Raw;
  RawSettings raw;
  GifSettings gif;
  BilateralSettings bilateral;
  AtrousSettings atrous;
  AafSettings aaf;  // also used by aaf_ao
  SspsfSettings sspsf;
  HpsfSettings hpsf;
  SvgfSettings svgf;
  TemporalSettings temporal;
  LightSettings lights;               // next-event estimation's light sampler
  ReservoirSettings reservoirs;       // every method's primary direct light from picked point and spot lights
  uint32_t maxBounces = 1;            // indirect bounces B, [1, 32] (B = 0 would be direct light only).
                                      // nhpsf and anhpsf gather every bounce through the map (each cell
                                      // reads the next vertex's, over frames) whatever B says
  uint32_t russianRouletteStart = 3;  // bounce from which paths may stop early (unbiased), [1, 64]
  uint64_t rayBudget = 0;             // rays per frame; 0 = unlimited. The module lowers its sample
                                      // count (never below 1 spp) from the rays per path it last measured
  DebugView debugView = DebugView::None;
  uint32_t seed = 1;  // random sequence; the same seed and inputs give the same frames
  // The engine lights the primary hits itself (its own shadow maps): no next-event estimation and no
  // reservoirs at the primary hits (FrameStats::raysTraced lower by their shadow rays), the direct output
  // 0 and the composite diffuse albedo × indirect (emission, sky and direct light are the engine's).
  bool indirectOnly = false;
};

// The knob --spp and the ray budget act on: the active method's paths per pixel.
uint32_t tracedSamplesPerPixel(const Settings& settings);         // 0 for AAF (adaptive)
void setTracedSamplesPerPixel(Settings& settings, uint32_t spp);  // no effect for AAF
// The hash map capacity in cells for a render size (settings.hpsf.capacity, or its default: a quarter cell a
// pixel; for nhpsf and anhpsf at least a third of a cell a vertex their paths reach, up to 2^19 cells).
uint32_t hashCapacity(const Settings& settings, uint32_t width, uint32_t height);
// How much wider than the first vertex's the cells after it are for a render size: nhpsf and anhpsf
// widen them (by a power of two, up to 16) until the cells their vertices keep live fit the map at about
// half load, never below hpsf.secondary_width; hpsf.secondary_width for the other methods.
float hashSecondaryWidth(const Settings& settings, uint32_t width, uint32_t height);
bool usesScreenFilters(
    Method method);                // the filters of screen_filters (every method but raw, the hash methods and svgf)
bool isAaf(Method method);         // aaf, aaf_ao: adaptive sample counts (tracedSamplesPerPixel is 0)
bool usesHashGrid(Method method);  // hpsf, nhpsf, anhpsf: the persistent world-space hash map
bool usesTemporalReprojection(const Settings& settings);  // the method reprojects last frame's light (TemporalSettings)

}  // namespace gi
