// The catalogues of gi/catalogue.h. A setting's range here is the range
// validate() enforces, the range --set documents and the range of its slider.
#include "gi/catalogue.h"

#include <algorithm>
#include <cstdio>

#include "shared/gi_filters.h"
#include "shared/hash_grid.h"

namespace gi {
namespace {

constexpr uint32_t bit(Method m) { return 1u << uint32_t(m); }
constexpr uint32_t kRaw = bit(Method::Raw), kGif = bit(Method::Gif), kBilateral = bit(Method::Bilateral),
                   kAtrous = bit(Method::Atrous), kAaf = bit(Method::Aaf) | bit(Method::AafAo),
                   kSspsf = bit(Method::Sspsf), kNhpsf = bit(Method::Nhpsf), kAnhpsf = bit(Method::Anhpsf),
                   kHash = bit(Method::Hpsf) | kNhpsf | kAnhpsf,
                   kTemporal = kRaw | kGif | kBilateral | kAtrous | kSspsf | kHash, kSvgf = bit(Method::Svgf),
                   kEvery = kTemporal | kAaf | kSvgf;

// One row per field: the key, the field's path (for errors), unit, meaning, range and the methods reading it.
#define GI_SETTING(key, member, unit, meaning, kind, lo, hi, openMin, methods)            \
  SettingInfo {                                                                           \
    key, "settings." #member, unit, meaning, SettingKind::kind, lo, hi, openMin, methods, \
        [](const Settings& s) { return double(s.member); },                               \
        [](Settings& s, double v) { s.member = decltype(s.member)(v); }                   \
  }
#define GI_BOOL(key, member, meaning, methods)                                                                     \
  SettingInfo {                                                                                                    \
    key, "settings." #member, "", meaning, SettingKind::Bool, 0, 1, false, methods,                                \
        [](const Settings& s) { return s.member ? 1.0 : 0.0; }, [](Settings& s, double v) { s.member = v != 0.0; } \
  }
#define GI_CHOICE(key, member, meaning, hi, methods)                                   \
  SettingInfo {                                                                        \
    key, "settings." #member, "", meaning, SettingKind::Choice, 0, hi, false, methods, \
        [](const Settings& s) { return double(uint32_t(s.member)); },                  \
        [](Settings& s, double v) { s.member = decltype(s.member)(uint32_t(v)); }      \
  }

// Marks a row whose change restarts the histories (SettingInfo::restartsHistory).
SettingInfo restartsHistory(SettingInfo s) {
  s.restartsHistory = true;
  return s;
}

constexpr double kLastView = double(kDebugViewCount - 1);
constexpr const char* kTemporalMeaning =
    "blend in last frame's light, reprojected through the motion vectors (temporal.*)";

const SettingInfo kSettings[] = {
    restartsHistory(GI_SETTING("bounces", maxBounces, "", "indirect bounces B (0 would be direct light only)", Uint, 1,
                               32, false, 0)),
    GI_SETTING("rr_start", russianRouletteStart, "", "bounce from which paths may stop early (Russian roulette)", Uint,
               1, 64, false, 0),
    GI_SETTING("ray_budget", rayBudget, "rays per frame",
               "the module lowers its sample count to stay within it; 0 = unlimited", Uint, 0, 1e12, false, 0),
    GI_SETTING("seed", seed, "", "random sequence: the same seed and inputs give the same frames", Uint, 0,
               4294967295.0, false, 0),
    restartsHistory(GI_BOOL("indirect_only", indirectOnly,
                            "the engine lights the primary hits: no primary shadow rays, direct output 0", 0)),
    GI_CHOICE("view", debugView, "debug view (gi::debugViewCatalogue; 0 = the lit image)", kLastView, 0),

    GI_SETTING("raw.spp", raw.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint, 1, 64,
               false, kRaw),
    GI_BOOL("raw.accumulate", raw.temporalAccumulation, "average frames while the camera and settings stay", kRaw),
    restartsHistory(GI_BOOL("raw.temporal", raw.temporalReprojection, kTemporalMeaning, kRaw)),
    GI_SETTING("raw.history", raw.maxAccumulatedFrames, "frames", "accumulation cap; older frames fade out past it",
               Uint, 1, 1 << 20, false, kRaw),

    GI_SETTING("gif.spp", gif.samplesPerPixel, "paths per pixel", "indirect paths per guide ray", Uint, 1, 64, false,
               kGif),
    GI_SETTING("gif.radius", gif.radius, "pixels", "window radius (cost does not depend on it)", Uint, 1,
               GIF_MAX_RADIUS, false, kGif),
    GI_SETTING("gif.subsample", gif.subsample, "pixels per axis",
               "one window-statistics pixel per s×s pixels (fast guided filter): memory ÷ s²", Uint, 1,
               GIF_MAX_SUBSAMPLE, false, kGif),
    GI_SETTING("gif.eps_normal", gif.epsilonNormal, "", "ridge term of the normal channels (guidance in [0, 1])", Float,
               0, 1e6, false, kGif),
    GI_SETTING("gif.eps_depth", gif.epsilonDepth, "", "ridge term of the depth channel", Float, 0, 1e6, false, kGif),
    GI_SETTING("gif.dims", gif.guidanceDimensions, "", "guidance: 1 grey normal, 3 normal, 4 normal + depth", Uint, 1,
               4, false, kGif),
    GI_SETTING("gif.supersamples", gif.supersamples, "rays per pixel", "extra eye rays with geometry-aware lookup",
               Uint, 0, 16, false, kGif),
    restartsHistory(GI_BOOL("gif.temporal", gif.temporalReprojection, kTemporalMeaning, kGif)),

    GI_SETTING("bilateral.spp", bilateral.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint,
               1, 64, false, kBilateral),
    GI_SETTING("bilateral.radius", bilateral.radius, "pixels", "filter radius (cost grows with its square)", Uint, 1,
               64, false, kBilateral),
    GI_SETTING("bilateral.sigma_spatial", bilateral.sigmaSpatial, "pixels", "spatial sigma", Float, 0, 1e4, true,
               kBilateral),
    GI_SETTING("bilateral.sigma_normal", bilateral.sigmaNormal, "", "normal sigma (on normal·0.5+0.5)", Float, 0, 1e4,
               true, kBilateral),
    GI_SETTING("bilateral.sigma_depth", bilateral.sigmaDepth, "", "depth sigma, relative to the centre's depth", Float,
               0, 1e4, true, kBilateral),
    restartsHistory(GI_BOOL("bilateral.temporal", bilateral.temporalReprojection, kTemporalMeaning, kBilateral)),

    GI_SETTING("atrous.spp", atrous.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint, 1, 64,
               false, kAtrous),
    GI_SETTING("atrous.iterations", atrous.iterations, "", "wavelet iterations (taps up to 2^(n+1) pixels away)", Uint,
               1, 8, false, kAtrous),
    GI_SETTING("atrous.sigma_color", atrous.sigmaColor, "", "colour stop in demodulated radiance, halved per iteration",
               Float, 0, 1e6, true, kAtrous),
    GI_SETTING("atrous.sigma_normal", atrous.sigmaNormal, "", "normal stop (on normal·0.5+0.5)", Float, 0, 1e4, true,
               kAtrous),
    GI_SETTING("atrous.sigma_position", atrous.sigmaPosition, "",
               "position stop, a fraction of the centre's view depth", Float, 0, 1e4, true, kAtrous),
    restartsHistory(GI_BOOL("atrous.temporal", atrous.temporalReprojection, kTemporalMeaning, kAtrous)),

    GI_SETTING("aaf.mu", aaf.mu, "", "filter scale mu (> 1 narrows filters and raises sample counts)", Float, 0, 16,
               true, kAaf),
    GI_SETTING("aaf.alpha", aaf.alpha, "", "pixel-space band limit alpha", Float, 0, 1, true, kAaf),
    GI_SETTING("aaf.normal_limit", aaf.normalLimitDegrees, "degrees",
               "neighbours whose normals differ more are not filtered in", Float, 0, 180, false, kAaf),
    GI_SETTING("aaf.uniform", aaf.uniformSamples, "samples per pixel",
               "0 = adaptive; N >= 16 = N samples in every pixel (Fig. 10's filtered uniform)", Uint, 0, 1024, false,
               kAaf),
    GI_SETTING("aaf.max_radius", aaf.maxRadius, "pixels", "filter radius cap (0 = 3 sigma, the paper's)", Uint, 0, 1024,
               false, kAaf),

    GI_SETTING("sspsf.spp", sspsf.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint, 1, 64,
               false, kSspsf),
    GI_SETTING("sspsf.window", sspsf.window, "pixels", "odd window side", Uint, 1, 31, false, kSspsf),
    GI_SETTING("sspsf.width", sspsf.filterWidth, "pixels", "filter width (the HPSF cell of this width)", Float, 0.5,
               256, false, kSspsf),
    GI_SETTING("sspsf.normal_limit", sspsf.normalLimitDegrees, "degrees", "normal rejection angle", Float, 0, 180,
               false, kSspsf),
    restartsHistory(GI_BOOL("sspsf.temporal", sspsf.temporalReprojection, kTemporalMeaning, kSspsf)),

    GI_SETTING("temporal.min_blend", temporal.minBlend, "",
               "smallest weight of the new frame (history about 2/x - 1 frames)", Float, 0, 1, true, kTemporal),
    GI_SETTING("temporal.depth_tolerance", temporal.depthTolerance, "",
               "relative depth difference a history tap may have", Float, 0, 10, true, kTemporal | kSvgf),
    GI_SETTING("temporal.normal_limit", temporal.normalLimitDegrees, "degrees",
               "largest normal change a history tap may have", Float, 0, 180, false, kTemporal | kSvgf),
    GI_SETTING("temporal.filter_clamp", temporal.filterClamp, "standard deviations",
               "the filtered light stays within this many local sigma of the accumulated light (0 = off)", Float, 0, 10,
               false, kGif | kBilateral | kAtrous | kSspsf | kSvgf | kHash),
    GI_SETTING("temporal.history_clamp", temporal.historyClamp, "standard deviations",
               "the reprojected history stays within this many local sigma of this frame's samples (0 = off)", Float, 0,
               10, false, kTemporal | kSvgf),
    restartsHistory(GI_BOOL("temporal.gradients", temporal.gradients,
                            "A-SVGF temporal gradients: drop history where a re-traced sample says the light changed",
                            (kTemporal & ~kHash) | kSvgf)),

    GI_CHOICE("lights.sampler", lights.sampler,
              "NEE's light sampler: 0 the scene's, 1 every light, 2 one by power, 3 the tree's cut", 3, kEvery),
    restartsHistory(GI_BOOL("reservoirs.enabled", reservoirs.enabled,
                            "resample the primary hits' picked point and spot lights and many emissive triangles "
                            "through reservoirs (ReSTIR DI)",
                            kEvery)),
    restartsHistory(GI_SETTING("reservoirs.emissive_min", reservoirs.emissiveMin, "triangles",
                               "resample the emissive triangles where the scene has more than this many", Uint, 0,
                               1 << 22, false, kEvery)),
    GI_SETTING("reservoirs.candidates", reservoirs.candidates, "lights",
               "lights drawn per pixel and frame (raw's: raw_candidates)", Uint, 1, 64, false, kEvery),
    GI_BOOL("reservoirs.temporal", reservoirs.temporal,
            "merge last frame's reservoir through the motion vectors (where no temporal pass averages the direct "
            "light: raw, aaf)",
            kRaw | kAaf),
    GI_SETTING("reservoirs.neighbours", reservoirs.neighbours, "reservoirs",
               "neighbours merged (0 = no spatial reuse; raw's: raw_neighbours)", Uint, 0, 8, false, kEvery),
    GI_SETTING(
        "reservoirs.raw_candidates", reservoirs.rawCandidates, "lights",
        "raw's lights drawn per pixel and frame where its reservoirs merge and frames are not accumulated (no sky map)",
        Uint, 1, 64, false, kRaw),
    GI_SETTING(
        "reservoirs.raw_neighbours", reservoirs.rawNeighbours, "reservoirs",
        "raw's neighbours merged where its reservoirs merge and frames are not accumulated (no sky map; 0 = none)",
        Uint, 0, 8, false, kRaw),
    GI_SETTING("reservoirs.radius", reservoirs.radius, "pixels", "the disc the neighbours come from", Float, 1, 64,
               false, kEvery),
    GI_SETTING("reservoirs.max_history", reservoirs.maxHistory, "x candidates",
               "last frame's reservoir counts at most this many times the candidates", Float, 1, 1000, false, kEvery),
    GI_SETTING("reservoirs.sky_max_history", reservoirs.skyMaxHistory, "x candidates",
               "max_history while a sky map is in the reservoirs (sky, seen by some of its picks)", Float, 1, 1000,
               false, kRaw | kAaf),
    GI_BOOL("reservoirs.unbiased", reservoirs.unbiased,
            "spatial weights by the balance heuristic over the neighbours' surfaces (else the biased 1/M)", kEvery),
    GI_BOOL("reservoirs.pairwise", reservoirs.pairwise,
            "with unbiased: pairwise MIS against the pixel's own surface (2N+1 target evaluations, not (N+1)^2)",
            kEvery),
    GI_SETTING("reservoirs.boiling_filter", reservoirs.boilingFilter, "x the group's mean",
               "a temporal reservoir this many times its 8x8 group's others' mean estimate is dropped (0 = off)", Float,
               0, 1000, false, kEvery),
    GI_SETTING("reservoirs.group_candidates", reservoirs.groupCandidates, "draws per pixel",
               "the emissive triangles' candidates drawn for each 8x8 group, this many by each pixel, and shared: "
               "each pixel resamples its candidates from the group's (0 = each pixel draws its own)",
               Uint, 0, 8, false, kEvery),
    GI_SETTING("reservoirs.group_power_share", reservoirs.groupPowerShare, "",
               "with group_candidates: the share of the group's candidates drawn by power (the rest down the tree)",
               Float, 0, 1, true, kEvery),
    GI_BOOL("reservoirs.sky", reservoirs.sky,
            "where the reservoirs run, resample a sky map's light too (weighed against BSDF sampling)", kEvery),

    GI_SETTING("svgf.spp", svgf.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint, 1, 64,
               false, kSvgf),
    GI_SETTING("svgf.alpha", svgf.alpha, "", "smallest weight of the new frame's colour (the paper's alpha)", Float, 0,
               1, true, kSvgf),
    GI_SETTING("svgf.moments_alpha", svgf.momentsAlpha, "", "smallest weight of the new frame's luminance moments",
               Float, 0, 1, true, kSvgf),
    GI_SETTING("svgf.iterations", svgf.iterations, "", "a-trous iterations (0: accumulation only)", Uint, 0, 8, false,
               kSvgf),
    GI_SETTING("svgf.sigma_luminance", svgf.sigmaLuminance, "standard deviations", "luminance edge stop", Float, 0, 1e4,
               true, kSvgf),
    GI_SETTING("svgf.sigma_normal", svgf.sigmaNormal, "", "normal edge stop: the exponent on max(0, n.n')", Float, 0,
               1e4, true, kSvgf),
    GI_SETTING("svgf.sigma_depth", svgf.sigmaDepth, "depth gradients", "depth edge stop", Float, 0, 1e4, true, kSvgf),
    GI_BOOL("svgf.filter_direct", svgf.filterDirect, "filter the area lights' direct light too (off: accumulated only)",
            kSvgf),

    GI_SETTING("hpsf.spp", hpsf.samplesPerPixel, "paths per pixel", "paths traced per pixel per frame", Uint, 1, 64,
               false, kHash),
    GI_SETTING("hpsf.capacity", hpsf.capacity, "cells",
               "hash map size, a power of two >= 1024 (0 = from the render size; nhpsf, anhpsf: and their segments)",
               Uint, 0, kMaxHashCapacity, false, kHash),
    GI_SETTING("hpsf.probe_window", hpsf.probeWindow, "slots", "linear-probing limit", Uint, 1, 64, false, kHash),
    GI_SETTING("hpsf.width", hpsf.filterWidth, "pixels", "filter width: cell size = width x pixel footprint x distance",
               Float, 0.5, 256, false, kHash),
    GI_SETTING("hpsf.jitter", hpsf.jitter, "cells", "tangent-plane jitter, +- cells (0 = off)", Float, 0, 2, false,
               kHash),
    GI_SETTING("hpsf.normal_bits", hpsf.normalBits, "", "normal bins 2^b in all (0 = normals ignored)", Uint, 0,
               HG_MAX_NORMAL_BITS, false, kHash),
    GI_SETTING("hpsf.normal_jitter", hpsf.normalJitter, "bins", "normal jitter, +- bins (0 = off)", Float, 0, 2, false,
               kHash),
    GI_CHOICE("hpsf.secondary_lod", hpsf.secondaryLod,
              "LOD travel after the first vertex: 0 segment (thesis), 1 path, 2 camera", double(SecondaryLod::Camera),
              kNhpsf | kAnhpsf),
    GI_BOOL("hpsf.stochastic_lod", hpsf.stochasticLod, "pick between the two nearest levels at random", kHash),
    GI_SETTING("hpsf.clamp_sigma", hpsf.clampSigma, "sigma", "clamp samples above mean + k sigma of the cell (0 = off)",
               Float, 0, 100, false, kHash),
    GI_CHOICE("hpsf.eviction", hpsf.eviction, "eviction: 0 strict (the thesis's two tables), 1 aging",
              double(EvictionPolicy::Aging), kHash),
    GI_SETTING("hpsf.history", hpsf.historyFrames, "frames", "aging: history kept", Uint, 2, 10000, false, kHash),
    GI_SETTING("hpsf.history_samples", hpsf.historySamples, "samples",
               "aging: the mean a cell passes on to earlier vertices (0 = the pixel's mean)", Uint, 0, 1e6, false,
               kNhpsf | kAnhpsf),
    GI_SETTING("hpsf.stale", hpsf.staleFrames, "frames", "aging: untouched this long, a cell is evicted", Uint, 1,
               100000, false, kHash),
    GI_SETTING("hpsf.min_samples", hpsf.minSamples, "samples", "fewer in the cell: the pixel keeps its own", Uint, 1,
               1e6, false, kHash),
    GI_SETTING("hpsf.validation", hpsf.validationInterval, "frames",
               "aging: re-trace each cell's sentinel ray this often (0 = off)", Uint, 0, 1000, false, kHash),
    GI_BOOL("hpsf.deferred_claims", hpsf.deferredClaims,
            "aging: new cells are made after the frame's inserts, the largest key asking for a slot first, so a full "
            "map gives the same image every run (a new cell's first samples come a frame later)",
            kHash),
    GI_SETTING("hpsf.path_depth", hpsf.pathDepth, "segments", "nhpsf: path segments per pixel and frame", Uint, 1, 16,
               false, kNhpsf),
    GI_SETTING("hpsf.continuation_depth", hpsf.continuationDepth, "segments",
               "anhpsf: the longest path continued over frames", Uint, 2, 16, false, kAnhpsf),
    GI_SETTING("hpsf.secondary_width", hpsf.secondaryWidthScale, "",
               "cells after the first vertex are at least this much wider (more where the map needs it)", Float, 1, 16,
               false, kNhpsf | kAnhpsf),
    restartsHistory(GI_BOOL("hpsf.temporal", hpsf.temporalDirect,
                            "blend in last frame's direct light, reprojected (the map holds the indirect)", kHash)),
    restartsHistory(
        GI_BOOL("hpsf.temporal_indirect", hpsf.temporalIndirect,
                "with hpsf.temporal: accumulate the pixels' own indirect samples and hold the map's light near them "
                "(temporal.filter_clamp)",
                kHash)),
};

#undef GI_SETTING
#undef GI_BOOL
#undef GI_CHOICE

constexpr MethodInfo kMethods[] = {
    {Method::Raw, "raw", "unfiltered paths with NEE, optional temporal accumulation"},
    {Method::Gif, "gif", "guided image filter on demodulated indirect (Bauszat et al. 2011)"},
    {Method::Bilateral, "bilateral", "cross-bilateral filter on normal and depth (baseline)"},
    {Method::Atrous, "atrous", "edge-avoiding a-trous wavelets (Dammertz et al. 2010, baseline)"},
    {Method::Aaf, "aaf", "axis-aligned filtering with adaptive sampling (Mehta et al. 2013)"},
    {Method::AafAo, "aaf_ao", "axis-aligned filtering of ambient occlusion (Mehta et al. 2013)"},
    {Method::Sspsf, "sspsf", "screen-space path filtering (Meijer 2019)"},
    {Method::Hpsf, "hpsf", "hashed path space filtering on a persistent world-space hash map (Meijer 2019)"},
    {Method::Nhpsf, "nhpsf", "HPSF at every diffuse vertex of a path (Meijer 2019)"},
    {Method::Anhpsf, "anhpsf", "nHPSF amortised: each pixel continues one long path over frames (Meijer 2019)"},
    {Method::Svgf, "svgf", "spatiotemporal variance-guided filtering of direct and indirect (Schied et al. 2017)"},
};
static_assert(std::size(kMethods) == kMethodCount);
constexpr bool methodsInOrder() {
  for (uint32_t i = 0; i < std::size(kMethods); ++i)
    if (kMethods[i].method != Method(i)) return false;
  return true;
}
static_assert(methodsInOrder(), "kMethods follows gi::Method's order");

constexpr DebugViewInfo kViews[] = {
    {DebugView::None, "none (lit image)", "direct + diffuse albedo x indirect", true},
    {DebugView::Direct, "direct", "emission + direct light", true},
    {DebugView::Indirect, "indirect (demodulated)", "indirect light before the albedo", true},
    {DebugView::Albedo, "albedo", "the G-buffer's base colour", false},
    {DebugView::Normal, "normal", "the G-buffer's normal, mapped to [0, 1]", false},
    {DebugView::Guidance, "guidance", "screen filters: the normal as the guided filter sees it", false},
    {DebugView::GuidanceDepth, "guidance depth", "screen filters: the depth channel of the guidance", false},
    {DebugView::FilterInOut, "filter in | out", "left half the noisy indirect, right half filtered", true},
    {DebugView::GifCoefficients, "gif coefficients", "guided filter: |a| (red), |b| (green)", false},
    {DebugView::AafZMin, "aaf z_min", "AAF: nearest reflector distance / scene extent", false},
    {DebugView::AafZMax, "aaf z_max", "AAF: farthest reflector distance / scene extent", false},
    {DebugView::AafSamples, "aaf samples per pixel", "AAF: samples per pixel / 100", false},
    {DebugView::AafFilterWidth, "aaf filter width", "AAF: filter sigma in pixels / 32", false},
    {DebugView::HashCells, "hash cells", "HPSF: each pixel's cell, coloured by its key", false},
    {DebugView::HashLod, "hash level of detail", "HPSF: the cell's level of detail", false},
    {DebugView::HashSamples, "hash samples per cell", "HPSF: samples behind the cell's mean / 100", false},
    {DebugView::HashFound, "hash cell found", "HPSF: green used, yellow too few samples, red no cell", false},
    {DebugView::HashOccupancy, "hash occupancy", "HPSF: how full the probe window at the pixel's cell is", false},
    {DebugView::ContinuationDepth, "continuation depth", "A-nHPSF: the pixel's continued path / the maximum depth",
     false},
    {DebugView::TemporalHistory, "temporal history", "temporal reprojection: frames of history behind the pixel / 32",
     false},
    {DebugView::SvgfVariance, "svgf variance",
     "svgf: luminance variance of direct (red) and indirect (green), history frames / 32 (blue)", false},
    {DebugView::TemporalGradient, "temporal gradient",
     "temporal gradients: share of the history dropped, direct (red) and indirect (green)", false},
};
static_assert(std::size(kViews) == kDebugViewCount);
constexpr bool viewsInOrder() {
  for (uint32_t i = 0; i < std::size(kViews); ++i)
    if (kViews[i].view != DebugView(i)) return false;
  return true;
}
static_assert(viewsInOrder(), "kViews follows gi::DebugView's order");

constexpr PassInfo kPasses[] = {
    {Pass::ReservoirTemporal, "reservoir_temporal", false},
    {Pass::ReservoirSpatial, "reservoir_spatial", true},  // the survivor's shadow ray
    {Pass::ReservoirPick, "reservoir_pick", true},        // the temporal pass and the survivor's shadow ray
    {Pass::RawTrace, "raw_trace", true},
    {Pass::AafSample, "aaf_sample", true},
    {Pass::AafAdaptive, "aaf_adaptive", true},
    {Pass::HpsfInsert, "hpsf_insert", true},
    {Pass::NhpsfPaths, "nhpsf_paths", true},
    {Pass::AnhpsfPaths, "anhpsf_paths", true},
    {Pass::HpsfClaim, "hpsf_claim", false},
    {Pass::HpsfValidate, "hpsf_validate", false},  // its sentinel rays are a small part: not counted as tracing time
    {Pass::HpsfResolve, "hpsf_resolve", false},
    {Pass::HpsfLookup, "hpsf_lookup", false},
    {Pass::TemporalGradient, "temporal_gradient", true},
    {Pass::TemporalSpread, "temporal_spread", false},
    {Pass::Temporal, "temporal", false},
    {Pass::SvgfVariance, "svgf_variance", false},
    {Pass::SvgfAtrous, "svgf_atrous", false},
    {Pass::Guidance, "guidance", false},
    {Pass::Sspsf, "sspsf", false},
    {Pass::Bilateral, "bilateral", false},
    {Pass::Atrous, "atrous", false},
    {Pass::GifMoments, "gif_moments", false},
    {Pass::GifBoxRows, "gif_box_rows", false},
    {Pass::GifBoxColumns, "gif_box_columns", false},
    {Pass::GifCoefficients, "gif_coefficients", false},
    {Pass::GifOutput, "gif_output", false},
    {Pass::AafFilterDiffuseRows, "aaf_filter_diffuse_rows", false},
    {Pass::AafFilterDiffuseColumns, "aaf_filter_diffuse_columns", false},
    {Pass::AafFilterGlossyRows, "aaf_filter_glossy_rows", false},
    {Pass::AafFilterGlossyColumns, "aaf_filter_glossy_columns", false},
    {Pass::AafFilterGlossyEdgeRows, "aaf_filter_glossy_edge_rows", false},
    {Pass::AafFilterGlossyEdgeColumns, "aaf_filter_glossy_edge_columns", false},
    {Pass::Composite, "composite", false},
    {Pass::GifSupersample, "gif_supersample", true},
};
static_assert(std::size(kPasses) == size_t(Pass::Count));
constexpr bool passesInOrder() {
  for (uint32_t i = 0; i < std::size(kPasses); ++i)
    if (kPasses[i].pass != Pass(i)) return false;
  return true;
}
static_assert(passesInOrder(), "kPasses follows gi::Pass's order");

}  // namespace

std::span<const SettingInfo> settingCatalogue() { return kSettings; }

const SettingInfo* findSetting(std::string_view key) {
  for (const SettingInfo& s : kSettings)
    if (key == s.key) return &s;
  return nullptr;
}

std::string rangeText(const SettingInfo& k) {
  char text[96];
  if (k.kind == SettingKind::Float)
    std::snprintf(text, sizeof(text), "%s%g, %g]", k.openMin ? "(" : "[", k.min, k.max);
  else
    std::snprintf(text, sizeof(text), "[%.0f, %.0f]", k.min, k.max);
  return text;
}

bool inRange(const SettingInfo& k, double v) { return (k.openMin ? v > k.min : v >= k.min) && v <= k.max; }

std::string outOfRangeText(const SettingInfo& k, double v) {
  char value[64];
  std::snprintf(value, sizeof(value), k.kind == SettingKind::Float ? "%g" : "%.0f", v);
  return std::string(k.field) + " = " + value + " is outside " + rangeText(k);
}

std::span<const MethodInfo> methodCatalogue() { return kMethods; }
std::span<const DebugViewInfo> debugViewCatalogue() { return kViews; }
std::span<const PassInfo> passCatalogue() { return kPasses; }

bool passTracesRays(std::string_view name) {
  for (const PassInfo& p : kPasses)
    if (name == p.name) return p.tracesRays;
  return false;
}

const char* methodName(Method method) {
  return uint32_t(method) < kMethodCount ? kMethods[uint32_t(method)].name : "unknown";
}

bool methodFromName(const std::string& name, Method& out) {
  for (const MethodInfo& m : kMethods)
    if (name == m.name) {
      out = m.method;
      return true;
    }
  return false;
}

}  // namespace gi
