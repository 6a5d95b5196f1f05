// What a method runs for a scene: every decision about passes, images and
// programs, made once from the settings and the scene's facts (planMethod),
// and read by allocation (sized_resources.cpp), program creation
// (programs.cpp) and recording (frame.cpp). The module keeps the plan of the
// settings it runs (Module::plan); a caller asking about other settings (a
// switch being prepared, a memory prediction) plans them on the spot.
#pragma once

#include <cstdint>

#include "gi/gi.h"

namespace gi {

struct MethodPlan {
  Method method = Method::Raw;
  bool hashGrid = false;       // the persistent world-space hash map's passes (hpsf, nhpsf, anhpsf)
  bool screenFilters = false;  // a screen-space filter after the trace (gif, bilateral, à-trous, aaf, sspsf)
  // Its programs read the position image (à-trous, AAF, sspsf); gif's and bilateral's take coverage from
  // the guidance's depth, and the guidance pass writes no positions for them.
  bool filterPositions = false;
  bool aaf = false;                  // AAF's adaptive sample passes (aaf, aaf_ao)
  bool aafSpecular = false;          // AAF with glossy receivers in the scene: their specular terms filtered apart
  bool svgf = false;                 // svgf's variance and à-trous passes
  bool gifSupersamples = false;      // gif's extra eye rays after the composite
  uint32_t lightSampler = 0;         // NEE's light sampler (gpu::LIGHT_SAMPLER_*): the setting's, or the scene's
  bool picksPunctualLights = false;  // NEE picks one of several punctual lights (noise the temporal pass averages)
  // Direct light has noise to average only from area lights (emissive triangles, a sky) and from punctual
  // lights NEE picks one of.
  bool noisyDirect = false;
  // The temporal pass runs (its images and program exist) when the method reprojects and there is
  // something to reproject: the hash methods reproject their direct light, so not without area lights,
  // unless they clamp.
  bool temporalPass = false;
  // The hash methods with hpsf.temporal, hpsf.temporalIndirect and the filter clamp also accumulate each
  // pixel's own indirect sample, which the map's light is held against.
  bool clampsHashIndirect = false;
  // The hash methods' direct light alone is reprojected: its history is one packed image
  // (GI_BINDING_HISTORY_PACKED) that the composite pass writes.
  bool packedHistory = false;
  // Otherwise the temporal pass reads last frame's normal and depth from one history guide
  // (GI_BINDING_HISTORY_GUIDE), which a later pass replaces with this frame's: svgf's variance pass (its
  // à-trous iterations read it), else the composite pass.
  bool historyGuide = false;
  // Temporal gradients are traced (raw's trace pass) when the temporal pass runs for a method whose paths
  // start there (not the hash methods, not AAF).
  bool temporalGradients = false;
  bool historyClamp = false;  // the temporal pass clamps the history to this frame's samples
  // The screen filters read the indirect history the temporal pass wrote this frame, not a noisy image of
  // their own: the noisy indirect is then traced into the indirect output, which the temporal pass reads
  // pixel by pixel before the filter overwrites it (one image less). Not with the filter in | out view,
  // which shows the noisy image beside the output: the temporal pass then hands the filters its result
  // in the noisy image, as before.
  bool filtersReadHistory = false;
  bool reservoirs = false;  // the reservoir passes: reservoirPunctual or reservoirEmissive
  // The reservoirs resample the point and spot lights where NEE would pick among them, and the emissive
  // triangles where there are more than ReservoirSettings::emissiveMin of them (and at most 2^22: the
  // reservoir's word keeps 8 bits for the sample point); the rest stays NEE's.
  bool reservoirPunctual = false;
  bool reservoirEmissive = false;
  // Where the reservoir passes run anyway, they resample the sky too where it has a map
  // (ReservoirSettings::sky); a sky alone adds no reservoir pass: its NEE stays the vertex's.
  bool reservoirSky = false;
  // Last frame's reservoir is merged (ReservoirSettings::temporal) only where no temporal pass averages the
  // direct light over frames: the reuse makes a pixel's successive picks alike, and a history of alike
  // samples averages less noise away than one of fresh picks (docs/RESULTS.md, "Reservoirs").
  bool reservoirTemporal = false;
  // The candidates and neighbours a frame's reservoirs take: raw's own (ReservoirSettings::rawCandidates,
  // rawNeighbours) where its reservoirs merge, its frames are not accumulated and no sky map is among them;
  // else ReservoirSettings::candidates and neighbours.
  uint32_t reservoirCandidates = 0;
  uint32_t reservoirNeighbours = 0;
  // Without neighbours (and no sky map, whose failed directions the spatial pass writes where other pixels'
  // reprojections read) one pass draws, merges and traces the survivor's shadow ray (GI_RESERVOIR_PICK).
  bool reservoirPickPass = false;
  bool validatesHashCells = false;  // the hash map's sentinel rays are re-traced (aging with hpsf.validation > 0)
  bool defersHashClaims = false;    // new cells are made after the inserts (aging with hpsf.deferred_claims)
};

MethodPlan planMethod(const SceneDesc& scene, const Settings& settings);

}  // namespace gi
