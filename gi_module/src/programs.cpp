// Which programs settings run, their creation, and the warm-up (programs.h).
#include "programs.h"

#include <cstring>
#include <string>

#include "aaf_adaptive.comp.compute.h"
#include "aaf_adaptive.comp.h"
#include "aaf_sample.comp.compute.h"
#include "aaf_sample.comp.h"
#include "gi_composite.comp.compute.h"
#include "gi_composite.comp.h"
#include "gi_guidance.comp.compute.h"
#include "gi_guidance.comp.h"
#include "gi_raw_trace.comp.compute.h"
#include "gi_raw_trace.comp.h"
#include "gi_reservoirs.comp.compute.h"
#include "gi_reservoirs.comp.h"
#include "gi_supersample.comp.compute.h"
#include "gi_supersample.comp.h"
#include "gi_temporal.comp.compute.h"
#include "gi_temporal.comp.h"
#include "gi_temporal_gradient.comp.compute.h"
#include "gi_temporal_gradient.comp.h"
#include "gi_temporal_spread.comp.compute.h"
#include "gi_temporal_spread.comp.h"
#include "hpsf_claim.comp.h"
#include "hpsf_insert.comp.compute.h"
#include "hpsf_insert.comp.h"
#include "hpsf_lookup.comp.compute.h"
#include "hpsf_lookup.comp.h"
#include "hpsf_resolve.comp.h"
#include "hpsf_validate.comp.compute.h"
#include "hpsf_validate.comp.h"
#include "nhpsf_paths.comp.compute.h"
#include "nhpsf_paths.comp.h"
#include "shared/aaf.h"
#include "svgf_atrous.comp.compute.h"
#include "svgf_atrous.comp.h"
#include "svgf_variance.comp.compute.h"
#include "svgf_variance.comp.h"

namespace gi {
namespace {

constexpr glm::uvec2 kTile{GI_GROUP_SIZE, GI_GROUP_SIZE};

// Creates what `list` holds that does not exist yet; the caller holds m.programsMutex.
vk::Status createMissing(Module& m, std::span<const ProgramUse> list) {
  const auto spec = moduleSpecialization(m);
  for (const ProgramUse& p : list) {
    if (p.program->pipeline) continue;
    if (p.sets == ProgramSets::Filter) {
      GI_TRY(createFilterLayout(m.gpu, m.filterPrograms));
      GI_TRY(vk::createComputeProgram(m.gpu, p.spirv, std::span(&m.filterPrograms.layout, 1), p.pushSize, p.group, spec,
                                      *p.program));
      continue;
    }
    if (!m.hashLayout) GI_TRY(createHashGridLayout(m.gpu, m.hashLayout));
    const VkDescriptorSetLayout layouts[] = {m.desc.scene.layout, m.frameLayout, m.hashLayout};
    const size_t count = p.sets == ProgramSets::FrameAndHash ? 3 : 2;
    GI_TRY(vk::createComputeProgram(m.gpu, p.spirv, std::span(layouts, count), p.pushSize, p.group, spec, *p.program));
  }
  return {};
}

// The placeholders the warm-up binds, for `settings`: 1×1 images, a 64-cell map.
vk::Status buildWarmup(Module& m, const Settings& s, WarmupResources& w) {
  GI_TRY(createOutputImages(m.gpu, 1, 1, m.desc, w.outputs));
  GI_TRY(createSizedResources(m, s, 1, 1, w.outputs, w.sized));
  if (usesHashGrid(s.method))
    GI_TRY(createHashGrid(m.gpu, m.hashLayout, 64, s.hpsf.eviction == EvictionPolicy::Strict ? 2u : 1u, 1, 1, 1,
                          s.method == Method::Anhpsf, w.hash));
  GI_TRY(vk::createImage(m.gpu, {1, 1}, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, w.gbuffer));
  vk::DescriptorWriter writer(w.sized.frameSets[0]);
  for (uint32_t binding : {gpu::GI_BINDING_GB_NORMAL, gpu::GI_BINDING_GB_ALBEDO, gpu::GI_BINDING_GB_MATERIAL,
                           gpu::GI_BINDING_GB_EMISSION, gpu::GI_BINDING_GB_MOTION, gpu::GI_BINDING_GB_DEPTH})
    writer.texture(binding, w.gbuffer.view);
  writer.write(m.gpu);
  w.built = true;
  return {};
}

void destroyWarmup(vk::Device& g, WarmupResources& w) {
  destroyHashGrid(g, w.hash);
  destroySizedResources(g, w.sized);
  destroyOutputImages(g, w.outputs);
  vk::destroyImage(g, w.gbuffer);
  w = WarmupResources{};
}

// Everything the warm-up binds moves to the layout its bindings declare.
void recordWarmupFirstUse(const vk::Device& g, VkCommandBuffer cmd, WarmupResources& w) {
  recordFirstUse(g, cmd, w.outputs, w.sized);
  recordScreenFiltersFirstUse(g, cmd, w.sized.filters);
  vk::imageBarrier(g, cmd, w.gbuffer.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                   VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

}  // namespace

std::vector<ProgramUse> programsFor(Module& m, const Settings& s) {
  const uint32_t t = uint32_t(m.desc.scene.traversal);
  const MethodPlan plan = planMethod(m.desc.scene, s);
  std::vector<ProgramUse> list;
  auto add = [&](const char* name, vk::ComputeProgram& program, std::span<const uint32_t> spirv, uint32_t push,
                 ProgramSets sets = ProgramSets::Frame, glm::uvec2 group = kTile) {
    list.push_back({name, &program, spirv, push, group, sets});
  };
  if (plan.reservoirs)
    add("gi_reservoirs", m.reservoirs, GI_SCENE_SPIRV(t, gi_reservoirs_comp), sizeof(gpu::GiReservoirPush));
  if (plan.aaf) {
    add("aaf_sample", m.aafSample, GI_SCENE_SPIRV(t, aaf_sample_comp), sizeof(gpu::AafPush));
    add("aaf_adaptive", m.aafAdaptive, GI_SCENE_SPIRV(t, aaf_adaptive_comp), sizeof(gpu::AafPush));
  } else if (plan.hashGrid) {
    const ProgramSets hash = ProgramSets::FrameAndHash;
    if (s.method == Method::Hpsf)
      add("hpsf_insert", m.hashInsert, GI_SCENE_SPIRV(t, hpsf_insert_comp), sizeof(gpu::HgPush), hash);
    else
      add("nhpsf_paths", m.hashPaths, GI_SCENE_SPIRV(t, nhpsf_paths_comp), sizeof(gpu::HgPush), hash);
    if (plan.defersHashClaims)
      add("hpsf_claim", m.hashClaim, spv_hpsf_claim_comp, sizeof(gpu::HgPush), hash, {64, 1});  // traces nothing
    if (plan.validatesHashCells)
      add("hpsf_validate", m.hashValidate, GI_SCENE_SPIRV(t, hpsf_validate_comp), sizeof(gpu::HgPush), hash, {64, 1});
    add("hpsf_resolve", m.hashResolve, spv_hpsf_resolve_comp, sizeof(gpu::HgPush), hash, {64, 1});  // traces nothing
    add("hpsf_lookup", m.hashLookup, GI_SCENE_SPIRV(t, hpsf_lookup_comp), sizeof(gpu::HgPush), hash);
  } else {
    add("gi_raw_trace", m.rawTrace, GI_SCENE_SPIRV(t, gi_raw_trace_comp), sizeof(gpu::GiRawPush));
    if (plan.temporalGradients)
      add("gi_temporal_gradient", m.temporalGradient, GI_SCENE_SPIRV(t, gi_temporal_gradient_comp),
          sizeof(gpu::GiRawPush));
  }
  if (plan.historyClamp)
    add("gi_temporal_spread", m.temporalSpread, GI_SCENE_SPIRV(t, gi_temporal_spread_comp),
        sizeof(gpu::GiTemporalPush));
  if (plan.temporalPass)
    add("gi_temporal", m.temporal, GI_SCENE_SPIRV(t, gi_temporal_comp), sizeof(gpu::GiTemporalPush));
  if (plan.svgf) {
    add("svgf_variance", m.svgfVariance, GI_SCENE_SPIRV(t, svgf_variance_comp), sizeof(gpu::GiSvgfPush));
    add("svgf_atrous", m.svgfAtrous, GI_SCENE_SPIRV(t, svgf_atrous_comp), sizeof(gpu::GiSvgfPush));
  }
  if (plan.screenFilters) {
    add("gi_guidance", m.guidancePass, GI_SCENE_SPIRV(t, gi_guidance_comp), sizeof(gpu::GiGuidancePush));
    for (FilterProgram f : filterProgramsOf(s.method)) {
      const FilterProgramInfo& info = filterProgramCatalogue()[size_t(f)];
      add(info.name, m.filterPrograms.*info.program, info.spirv, info.pushSize, ProgramSets::Filter, info.group);
    }
  }
  add("gi_composite", m.composite, GI_SCENE_SPIRV(t, gi_composite_comp), sizeof(gpu::GiCompositePush));
  if (plan.gifSupersamples)
    add("gi_supersample", m.supersample, GI_SCENE_SPIRV(t, gi_supersample_comp), sizeof(gpu::GiSupersamplePush));
  return list;
}

vk::Status createPrograms(Module& m, const Settings& s) { return createMissing(m, programsFor(m, s)); }

vk::Status ensurePrograms(Module& m, const Settings& s) {
  const std::lock_guard<std::mutex> lock(m.programsMutex);
  return createPrograms(m, s);
}

std::vector<vk::ComputeProgram*> scenePrograms(Module& m) {
  return {&m.rawTrace,  &m.composite,    &m.guidancePass, &m.supersample,      &m.aafSample,      &m.aafAdaptive,
          &m.temporal,  &m.svgfVariance, &m.svgfAtrous,   &m.temporalGradient, &m.temporalSpread, &m.hashInsert,
          &m.hashPaths, &m.hashClaim,    &m.hashValidate, &m.hashResolve,      &m.hashLookup,     &m.reservoirs};
}

void destroyPrograms(Module& m) {
  destroyWarmup(m.gpu, m.warmup);
  for (vk::ComputeProgram* p : scenePrograms(m)) vk::destroyComputeProgram(m.gpu, *p);
  destroyFilterPrograms(m.gpu, m.filterPrograms);
  if (m.hashLayout) m.gpu.fn.vkDestroyDescriptorSetLayout(m.gpu.device, m.hashLayout, m.gpu.allocator);
  m.hashLayout = VK_NULL_HANDLE;
}

std::vector<std::string> programNames(Module* m, const Settings& settings) {
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  std::vector<std::string> names;
  for (const ProgramUse& p : programsFor(*m, settings)) names.push_back(p.name);
  return names;
}

bool programsPrepared(Module* m, const Settings& settings) {
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  for (const ProgramUse& p : programsFor(*m, settings))
    if (!p.program->pipeline) return false;
  return true;
}

Error preparePrograms(Module* m, const Settings& settings) {
  if (Error e = validate(settings)) return e;
  if (vk::Status s = ensurePrograms(*m, settings)) return vulkanError("gi::preparePrograms", s);
  return {};
}

Error recordProgramWarmup(Module* m, const Settings& settings, VkCommandBuffer cmd, std::string_view program) {
  if (!cmd) return {ErrorCode::MissingHandle, "gi::recordProgramWarmup: the command buffer must be set"};
  if (Error e = validate(settings)) return e;
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  const std::vector<ProgramUse> list = programsFor(*m, settings);
  bool named = program.empty();
  for (const ProgramUse& p : list) named |= program == p.name;
  if (!named)
    return {ErrorCode::OutOfRange, "gi::recordProgramWarmup: program \"" + std::string(program) +
                                       "\" is not one these settings run (gi::programNames)"};
  if (m->warmup.built)
    return {ErrorCode::OutOfRange,
            "gi::recordProgramWarmup: the last warm-up is not finished (gi::finishProgramWarmup once it completed)"};
  vk::Status s = createMissing(*m, list);
  if (!s) s = buildWarmup(*m, settings, m->warmup);
  if (s) {
    destroyWarmup(m->gpu, m->warmup);
    return vulkanError("gi::recordProgramWarmup", s);
  }
  const vk::Device& g = m->gpu;
  WarmupResources& w = m->warmup;
  recordWarmupFirstUse(g, cmd, w);
  for (const ProgramUse& p : list) {
    if (!program.empty() && program != p.name) continue;
    const VkDescriptorSet frameSets[] = {m->desc.scene.set, w.sized.frameSets[0],
                                         w.hash.set.sets.empty() ? VK_NULL_HANDLE : w.hash.set[0]};
    const std::span<const VkDescriptorSet> sets =
        p.sets == ProgramSets::Filter
            ? std::span<const VkDescriptorSet>(&w.sized.filters.set.sets[0], 1)
            : std::span<const VkDescriptorSet>(frameSets, p.sets == ProgramSets::FrameAndHash ? 3 : 2);
    vk::warmUp(g, cmd, *p.program, sets);
  }
  return {};
}

void finishProgramWarmup(Module* m) {
  const std::lock_guard<std::mutex> lock(m->programsMutex);
  destroyWarmup(m->gpu, m->warmup);
}

}  // namespace gi
