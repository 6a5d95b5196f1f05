#include "hash_grid.h"

#include <algorithm>
#include <cstring>

#include "hpsf_insert.comp.h"
#include "hpsf_insert.comp.compute.h"
#include "hpsf_lookup.comp.h"
#include "hpsf_lookup.comp.compute.h"
#include "hpsf_resolve.comp.h"
#include "hpsf_resolve.comp.compute.h"
#include "nhpsf_paths.comp.h"
#include "nhpsf_paths.comp.compute.h"
#include "shared/gi_frame.h"

namespace gi {

HashGrid createHashGrid(const engine::Context& ctx, uint32_t capacity, uint32_t tables, uint32_t width, uint32_t height,
                        uint32_t slots, bool walks) {
  HashGrid g;
  g.capacity = capacity;
  g.tables = tables;
  const VkDeviceSize n = VkDeviceSize(capacity) * tables;
  // Transfer source too, so tools and tests can read the map back.
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  g.keys = engine::createBuffer(ctx, sizeof(uint32_t) * n, usage, engine::MemoryKind::DeviceLocal);
  g.accum = engine::createBuffer(ctx, sizeof(gpu::HgAccum) * n, usage, engine::MemoryKind::DeviceLocal);
  g.cells = engine::createBuffer(ctx, sizeof(gpu::HgCell) * n, usage, engine::MemoryKind::DeviceLocal);
  g.telemetry = engine::createBuffer(ctx, sizeof(gpu::HgTelemetry) * (1 + slots), usage,
                                     engine::MemoryKind::HostVisible);
  std::memset(g.telemetry.mapped, 0, g.telemetry.size);
  g.walkPixels = walks ? width * height : 0;
  g.walks = engine::createBuffer(ctx, sizeof(gpu::HgWalk) * std::max(g.walkPixels, 1u), usage, engine::MemoryKind::DeviceLocal);
  g.pixelCell = engine::createImage(ctx, {width, height}, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT);
  g.memoryBytes = g.keys.size + g.accum.size + g.cells.size + g.telemetry.size + g.walks.size + g.pixelCell.allocationSize;
  const engine::Binding bindings[] = {
      {gpu::HG_BINDING_KEYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::HG_BINDING_ACCUM, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::HG_BINDING_CELLS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::HG_BINDING_TELEMETRY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::HG_BINDING_PIXEL_CELL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {gpu::HG_BINDING_CONTINUATION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
  };
  g.set = engine::createDescriptorSet(ctx, bindings);
  engine::DescriptorWriter(g.set.set)
      .buffer(gpu::HG_BINDING_KEYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.keys.buffer)
      .buffer(gpu::HG_BINDING_ACCUM, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.accum.buffer)
      .buffer(gpu::HG_BINDING_CELLS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.cells.buffer)
      .buffer(gpu::HG_BINDING_TELEMETRY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.telemetry.buffer)
      .storageImage(gpu::HG_BINDING_PIXEL_CELL, g.pixelCell.view)
      .buffer(gpu::HG_BINDING_CONTINUATION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.walks.buffer)
      .write(ctx);
  return g;
}

void ensureHashGridPrograms(const engine::Context& ctx, HashGrid& g, const VkDescriptorSetLayout layouts[2],
                            std::span<const uint32_t> spec, uint32_t mode, uint32_t traversal) {
  VkDescriptorSetLayout all[] = {layouts[0], layouts[1], g.set.layout};
  const glm::uvec2 tile{GI_GROUP_SIZE, GI_GROUP_SIZE};
  auto make = [&](engine::ComputeProgram& p, std::span<const uint32_t> spirv, glm::uvec2 group) {
    if (!p.pipeline) p = engine::createComputeProgram(ctx, spirv, all, sizeof(gpu::HgPush), group, spec);
  };
  if (mode == gpu::HG_MODE_HPSF) make(g.insert, GI_SCENE_SPIRV(traversal, hpsf_insert_comp), tile);
  else make(g.paths, GI_SCENE_SPIRV(traversal, nhpsf_paths_comp), tile);
  make(g.resolve, GI_SCENE_SPIRV(traversal, hpsf_resolve_comp), {64, 1});
  make(g.lookup, GI_SCENE_SPIRV(traversal, hpsf_lookup_comp), tile);
}

void destroyHashGrid(const engine::Context& ctx, HashGrid& g) {
  for (engine::ComputeProgram* p : {&g.insert, &g.paths, &g.resolve, &g.lookup}) engine::destroyComputeProgram(ctx, *p);
  engine::destroyDescriptorSet(ctx, g.set);
  for (engine::Buffer* b : {&g.keys, &g.accum, &g.cells, &g.telemetry, &g.walks}) engine::destroyBuffer(ctx, *b);
  engine::destroyImage(ctx, g.pixelCell);
  g = HashGrid{};
}

uint32_t hashTableBase(const HashGrid& g, uint32_t frameIndex) { return (frameIndex % g.tables) * g.capacity; }
uint32_t previousHashTableBase(const HashGrid& g, uint32_t frameIndex) { return ((frameIndex + 1) % g.tables) * g.capacity; }

void recordHashGridFrameStart(VkCommandBuffer cmd, HashGrid& g, uint32_t frameIndex) {
  if (g.cleared && g.tables == 2) {  // strict: the table written this frame starts empty
    VkDeviceSize base = hashTableBase(g, frameIndex);
    vkCmdFillBuffer(cmd, g.keys.buffer, base * sizeof(uint32_t), g.capacity * sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, g.accum.buffer, base * sizeof(gpu::HgAccum), g.capacity * sizeof(gpu::HgAccum), 0);
    vkCmdFillBuffer(cmd, g.cells.buffer, base * sizeof(gpu::HgCell), g.capacity * sizeof(gpu::HgCell), 0);
  }
  if (!g.cleared) {
    vkCmdFillBuffer(cmd, g.keys.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, g.accum.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, g.cells.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, g.walks.buffer, 0, VK_WHOLE_SIZE, 0);  // state 0: no live walk
    engine::imageBarrier(cmd, g.pixelCell.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                         VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                         VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    g.cleared = true;
  }
  vkCmdFillBuffer(cmd, g.telemetry.buffer, 0, sizeof(gpu::HgTelemetry), 0);
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void recordHashGridTelemetryCopy(VkCommandBuffer cmd, HashGrid& g, uint32_t slot) {
  engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferCopy copy{0, sizeof(gpu::HgTelemetry) * (1 + slot), sizeof(gpu::HgTelemetry)};
  vkCmdCopyBuffer(cmd, g.telemetry.buffer, g.telemetry.buffer, 1, &copy);
}

gpu::HgTelemetry readHashGridTelemetry(const HashGrid& g, uint32_t slot) {
  gpu::HgTelemetry t{};
  if (g.telemetry.mapped)
    std::memcpy(&t, static_cast<const std::byte*>(g.telemetry.mapped) + sizeof(gpu::HgTelemetry) * (1 + slot), sizeof(t));
  return t;
}

}  // namespace gi
