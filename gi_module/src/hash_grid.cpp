#include "hash_grid.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "shared/gi_frame.h"

namespace gi {

namespace {
// The arrays with one element per slot of every table: created, cleared (whole, or the strict policy's
// table of the frame), bound and destroyed together.
struct SlotArray {
  vk::Buffer HashGrid::*buffer;
  uint32_t binding;
  VkDeviceSize elementBytes;
};
constexpr SlotArray kSlotArrays[] = {
    {&HashGrid::keys, gpu::HG_BINDING_KEYS, sizeof(uint32_t)},
    {&HashGrid::accum, gpu::HG_BINDING_ACCUM, sizeof(gpu::HgAccum)},
    {&HashGrid::counts, gpu::HG_BINDING_COUNTS, sizeof(uint32_t)},
    {&HashGrid::cells, gpu::HG_BINDING_CELLS, sizeof(gpu::HgCell)},
};
// Set 2: the slot arrays' bindings (derived, so an array and its binding are declared once), then the
// telemetry and anhpsf's continued paths.
constexpr auto kHashGridBindings = [] {
  std::array<vk::Binding, std::size(kSlotArrays) + 2> all{};
  size_t n = 0;
  for (const SlotArray& a : kSlotArrays) all[n++] = {a.binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
  all[n++] = {gpu::HG_BINDING_TELEMETRY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
  all[n++] = {gpu::HG_BINDING_CONTINUATION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
  return all;
}();
}  // namespace

vk::Status createHashGridLayout(const vk::Device& d, VkDescriptorSetLayout& out) {
  return vk::createDescriptorLayout(d, kHashGridBindings, out);
}

vk::Status createHashGrid(vk::Device& d, VkDescriptorSetLayout layout, uint32_t capacity, uint32_t tables,
                          uint32_t width, uint32_t height, uint32_t slots, bool walks, HashGrid& out) {
  HashGrid g;
  g.capacity = capacity;
  g.tables = tables;
  const VkDeviceSize n = VkDeviceSize(capacity) * tables;
  // Transfer source too, so tools and tests can read the map back.
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  g.walkPixels = walks ? width * height : 0;
  auto build = [&]() -> vk::Status {
    for (const SlotArray& a : kSlotArrays) GI_TRY(vk::createBuffer(d, a.elementBytes * n, usage, false, g.*a.buffer));
    GI_TRY(vk::createBuffer(d, sizeof(gpu::HgTelemetry) * (1 + slots), usage, true, g.telemetry));
    if (g.telemetry.memory.mapped) std::memset(g.telemetry.memory.mapped, 0, g.telemetry.size);  // null: a prediction
    GI_TRY(vk::createBuffer(d, sizeof(gpu::HgWalkRecord) * std::max(g.walkPixels, 1u), usage, false, g.walks));
    GI_TRY(vk::createDescriptorSets(d, kHashGridBindings, 1, g.set, layout));
    return {};
  };
  if (vk::Status s = build()) {
    destroyHashGrid(d, g);
    return s;
  }
  vk::DescriptorWriter writer(g.set[0]);
  g.memoryBytes = g.telemetry.memory.size + g.walks.memory.size;
  for (const SlotArray& a : kSlotArrays) {
    g.memoryBytes += (g.*a.buffer).memory.size;
    writer.buffer(a.binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, (g.*a.buffer).buffer);
  }
  writer.buffer(gpu::HG_BINDING_TELEMETRY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.telemetry.buffer)
      .buffer(gpu::HG_BINDING_CONTINUATION, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g.walks.buffer)
      .write(d);
  out = std::move(g);
  return {};
}

void destroyHashGrid(vk::Device& d, HashGrid& g) {
  vk::destroyDescriptorSets(d, g.set);
  for (const SlotArray& a : kSlotArrays) vk::destroyBuffer(d, g.*a.buffer);
  for (vk::Buffer* b : {&g.telemetry, &g.walks}) vk::destroyBuffer(d, *b);
  g = HashGrid{};
}

uint32_t hashTableBase(const HashGrid& g, uint32_t frameIndex) { return (frameIndex % g.tables) * g.capacity; }
uint32_t previousHashTableBase(const HashGrid& g, uint32_t frameIndex) {
  return ((frameIndex + 1) % g.tables) * g.capacity;
}

void recordHashGridFrameStart(const vk::Device& d, VkCommandBuffer cmd, HashGrid& g, uint32_t frameIndex) {
  if (g.cleared && g.tables == 2) {  // strict: the table written this frame starts empty
    const VkDeviceSize base = hashTableBase(g, frameIndex);
    for (const SlotArray& a : kSlotArrays)
      d.fn.vkCmdFillBuffer(cmd, (g.*a.buffer).buffer, base * a.elementBytes, g.capacity * a.elementBytes, 0);
  }
  if (!g.cleared) {
    for (const SlotArray& a : kSlotArrays) d.fn.vkCmdFillBuffer(cmd, (g.*a.buffer).buffer, 0, VK_WHOLE_SIZE, 0);
    g.cleared = true;
    g.walksCleared = false;
  }
  if (!g.walksCleared) {
    d.fn.vkCmdFillBuffer(cmd, g.walks.buffer, 0, VK_WHOLE_SIZE, 0);  // state 0: no live walk
    g.walksCleared = true;
  }
  d.fn.vkCmdFillBuffer(cmd, g.telemetry.buffer, 0, sizeof(gpu::HgTelemetry), 0);
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void recordHashGridTelemetryCopy(const vk::Device& d, VkCommandBuffer cmd, HashGrid& g, uint32_t slot) {
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferCopy copy{0, sizeof(gpu::HgTelemetry) * (1 + slot), sizeof(gpu::HgTelemetry)};
  d.fn.vkCmdCopyBuffer(cmd, g.telemetry.buffer, g.telemetry.buffer, 1, &copy);
}

gpu::HgTelemetry readHashGridTelemetry(const HashGrid& g, uint32_t slot) {
  gpu::HgTelemetry t{};
  if (g.telemetry.memory.mapped)
    std::memcpy(&t, static_cast<const std::byte*>(g.telemetry.memory.mapped) + sizeof(gpu::HgTelemetry) * (1 + slot),
                sizeof(t));
  return t;
}

}  // namespace gi
