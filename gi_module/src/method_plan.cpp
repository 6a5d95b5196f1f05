#include "method_plan.h"

#include "screen_filters.h"

namespace gi {

MethodPlan planMethod(const SceneDesc& scene, const Settings& s) {
  MethodPlan p;
  p.method = s.method;
  p.hashGrid = usesHashGrid(s.method);
  p.screenFilters = usesScreenFilters(s.method);
  p.filterPositions = filtersReadPositions(s.method);
  p.aaf = isAaf(s.method);
  p.aafSpecular = s.method == Method::Aaf && scene.hasGlossyMaterials;
  p.svgf = s.method == Method::Svgf;
  p.gifSupersamples = s.method == Method::Gif && s.gif.supersamples > 0;
  p.lightSampler = s.lights.sampler == LightSampling::Scene ? scene.lightSampler : uint32_t(s.lights.sampler) - 1;
  p.picksPunctualLights = p.lightSampler <= gpu::LIGHT_SAMPLER_TREE && scene.picksPunctualLightsWith[p.lightSampler];
  p.noisyDirect = !s.indirectOnly && (scene.hasEmissiveTriangles || scene.hasSky || p.picksPunctualLights);
  p.clampsHashIndirect =
      p.hashGrid && s.hpsf.temporalDirect && s.hpsf.temporalIndirect && s.temporal.filterClamp > 0.0f;
  p.temporalPass = usesTemporalReprojection(s) && (p.noisyDirect || !p.hashGrid || p.clampsHashIndirect);
  p.packedHistory = p.temporalPass && p.hashGrid && !p.clampsHashIndirect;
  p.historyGuide = p.temporalPass && !p.packedHistory;
  p.temporalGradients = s.temporal.gradients && p.temporalPass && !p.hashGrid && !p.aaf;
  p.historyClamp = s.temporal.historyClamp > 0.0f && p.temporalPass;
  p.filtersReadHistory = p.screenFilters && p.temporalPass && s.debugView != DebugView::FilterInOut;
  const bool resamples = s.reservoirs.enabled && !s.indirectOnly;
  p.reservoirPunctual = resamples && p.picksPunctualLights;
  p.reservoirEmissive =
      resamples && scene.emissiveTriangles > s.reservoirs.emissiveMin && scene.emissiveTriangles <= (1u << 22);
  p.reservoirs = p.reservoirPunctual || p.reservoirEmissive;
  p.reservoirSky = p.reservoirs && scene.hasSky && s.reservoirs.sky;
  p.reservoirTemporal = p.reservoirs && s.reservoirs.temporal && !p.temporalPass;
  const bool rawBudget =
      p.reservoirTemporal && s.method == Method::Raw && !s.raw.temporalAccumulation && !p.reservoirSky;
  p.reservoirCandidates = rawBudget ? s.reservoirs.rawCandidates : s.reservoirs.candidates;
  p.reservoirNeighbours = rawBudget ? s.reservoirs.rawNeighbours : s.reservoirs.neighbours;
  p.reservoirPickPass = p.reservoirs && p.reservoirNeighbours == 0 && !p.reservoirSky;
  p.validatesHashCells = p.hashGrid && s.hpsf.eviction == EvictionPolicy::Aging && s.hpsf.validationInterval > 0;
  p.defersHashClaims = p.hashGrid && s.hpsf.eviction == EvictionPolicy::Aging && s.hpsf.deferredClaims;
  return p;
}

}  // namespace gi
