#include "gi/vk/memory_arena.h"

#include <algorithm>

#include "gi/vk/device.h"

namespace gi::vk {
namespace {

VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return a > 1 ? (v + a - 1) / a * a : v; }

bool findMemoryType(const Device& d, uint32_t typeBits, VkMemoryPropertyFlags flags, uint32_t& out) {
  for (uint32_t i = 0; i < d.memoryProperties.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (d.memoryProperties.memoryTypes[i].propertyFlags & flags) == flags) {
      out = i;
      return true;
    }
  return false;
}

// First fit in one block: the offset, or false.
bool carve(MemoryArena::Block& b, VkDeviceSize size, VkDeviceSize alignment, VkDeviceSize& offset) {
  for (size_t i = 0; i < b.free.size(); ++i) {
    MemoryArena::Range r = b.free[i];
    VkDeviceSize start = alignUp(r.offset, alignment);
    if (start + size > r.offset + r.size) continue;
    VkDeviceSize tail = r.offset + r.size - (start + size);
    b.free.erase(b.free.begin() + ptrdiff_t(i));
    if (tail > 0) b.free.insert(b.free.begin() + ptrdiff_t(i), {start + size, tail});
    if (start > r.offset) b.free.insert(b.free.begin() + ptrdiff_t(i), {r.offset, start - r.offset});
    offset = start;
    return true;
  }
  return false;
}

// The size of the next shared block of a kind (memory type, linear or not,
// mapped or not): doubling with the shared blocks of that kind alive.
VkDeviceSize sharedBlockSize(const MemoryArena& a, uint32_t type, bool linear, bool hostVisible) {
  uint32_t live = 0;
  for (const MemoryArena::Block& b : a.blocks)
    live += b.memory && b.shared && b.memoryType == type && b.linear == linear && b.hostVisible == hostVisible;
  return std::min(a.maxBlockSize, a.firstBlockSize << std::min(live, 16u));
}

// `size` more bytes held within the budget, or the error a full heap gives.
Status withinBudget(const MemoryArena& a, VkDeviceSize size) {
  if (a.budget && a.held + size > a.budget)
    return {VK_ERROR_OUT_OF_DEVICE_MEMORY, "an allocation within ModuleDesc::memoryBudgetBytes"};
  return {};
}

Status newBlock(Device& d, uint32_t type, VkDeviceSize size, bool shared, bool hostVisible, bool linear,
                uint32_t& index) {
  MemoryArena& a = d.memory;
  GI_TRY(withinBudget(a, size));
  MemoryArena::Block b;
  b.size = size;
  b.memoryType = type;
  b.shared = shared;
  b.linear = linear;
  b.hostVisible = hostVisible;
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  if (d.deviceAddressMemory) info.pNext = &flags;
  info.allocationSize = size;
  info.memoryTypeIndex = type;
  if (a.simulate)
    b.memory = reinterpret_cast<VkDeviceMemory>(a.nextPlaceholder++);
  else
    GI_VK(d.fn.vkAllocateMemory(d.device, &info, d.allocator, &b.memory));
  if (hostVisible && !a.simulate) {
    if (VkResult r = d.fn.vkMapMemory(d.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped); r != VK_SUCCESS) {
      d.fn.vkFreeMemory(d.device, b.memory, d.allocator);
      return {r, "vkMapMemory"};
    }
  }
  b.free.push_back({0, size});
  auto slot = std::find_if(a.blocks.begin(), a.blocks.end(), [](const MemoryArena::Block& x) { return !x.memory; });
  index = uint32_t(slot - a.blocks.begin());
  if (slot == a.blocks.end())
    a.blocks.push_back(std::move(b));
  else
    *slot = std::move(b);
  a.held += size;
  a.allocations++;
  return {};
}

// One resource's memory from the engine's callbacks, checked: the module binds what it is given.
Status engineAllocate(Device& d, const DeviceMemoryRequest& request, Allocation& out) {
  MemoryArena& a = d.memory;
  const VkDeviceSize size = request.requirements.size;
  GI_TRY(withinBudget(a, size));
  DeviceMemorySlice slice;
  if (a.simulate) {
    slice.memory = reinterpret_cast<VkDeviceMemory>(a.nextPlaceholder++);
  } else {
    if (VkResult r = a.engine.allocate(a.engine.userData, request, slice); r != VK_SUCCESS)
      return {r, "DeviceMemoryCallbacks::allocate"};
    const VkDeviceSize alignment = std::max<VkDeviceSize>(request.requirements.alignment, 1);
    const bool hostVisible = request.properties & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    const char* wrong = !slice.memory ? "DeviceMemoryCallbacks::allocate returned no memory"
                        : slice.offset % alignment != 0
                            ? "DeviceMemoryCallbacks::allocate returned an offset off the alignment"
                        : hostVisible && slice.mapped == nullptr
                            ? "DeviceMemoryCallbacks::allocate returned no mapped pointer for host-visible memory"
                            : nullptr;
    if (wrong) {
      slice.size = size;
      if (slice.memory && a.engine.free) a.engine.free(a.engine.userData, slice);
      return {VK_ERROR_INITIALIZATION_FAILED, wrong};
    }
  }
  a.held += size;
  a.used += size;
  out.memory = slice.memory;
  out.offset = slice.offset;
  out.size = size;
  out.mapped = slice.mapped;
  out.block = kEngineMemory;
  return {};
}

}  // namespace

Status allocate(Device& d, const VkMemoryRequirements& req, bool hostVisible, bool linear, bool transient,
                Allocation& out) {
  MemoryArena& a = d.memory;
  const std::lock_guard<std::mutex> guard(a.lock.mutex);
  const VkMemoryPropertyFlags flags = hostVisible
                                          ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                          : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  if (a.engine.enabled()) {
    const VkMemoryAllocateFlags allocateFlags = d.deviceAddressMemory ? VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT : 0;
    return engineAllocate(d, {req, flags, allocateFlags, linear, transient}, out);
  }
  uint32_t type = 0;
  if (!findMemoryType(d, req.memoryTypeBits, flags, type))
    return {VK_ERROR_FEATURE_NOT_PRESENT,
            hostVisible ? "a host-visible coherent memory type" : "a device-local memory type"};
  uint32_t index = UINT32_MAX;
  VkDeviceSize offset = 0;
  const VkDeviceSize blockSize = sharedBlockSize(a, type, linear, hostVisible);
  const bool ownBlock = req.size * 2 >= blockSize;
  if (!ownBlock)
    for (uint32_t i = 0; i < a.blocks.size(); ++i) {
      MemoryArena::Block& b = a.blocks[i];
      if (b.memory && b.shared && b.memoryType == type && b.linear == linear && b.hostVisible == hostVisible &&
          carve(b, req.size, req.alignment, offset)) {
        index = i;
        break;
      }
    }
  if (index == UINT32_MAX) {
    VkDeviceSize size = ownBlock ? req.size : blockSize;
    // Under a budget a small resource may still fit in a block of its own size.
    const bool shared = !ownBlock && !withinBudget(a, size);
    if (!shared) size = req.size;
    GI_TRY(newBlock(d, type, size, shared, hostVisible, linear, index));
    carve(a.blocks[index], req.size, req.alignment, offset);
  }
  MemoryArena::Block& b = a.blocks[index];
  b.used += req.size;
  a.used += req.size;
  out.memory = b.memory;
  out.offset = offset;
  out.size = req.size;
  out.block = index;
  out.mapped = b.mapped ? static_cast<char*>(b.mapped) + offset : nullptr;
  return {};
}

void release(Device& d, Allocation& al) {
  MemoryArena& a = d.memory;
  const std::lock_guard<std::mutex> guard(a.lock.mutex);
  if (al.block == kEngineMemory) {
    if (!a.simulate) a.engine.free(a.engine.userData, {al.memory, al.offset, al.size, al.mapped});
    a.held -= al.size;
    a.used -= al.size;
    al = Allocation{};
    return;
  }
  if (al.block >= a.blocks.size()) return;
  MemoryArena::Block& b = a.blocks[al.block];
  auto it = std::lower_bound(b.free.begin(), b.free.end(), al.offset,
                             [](const MemoryArena::Range& r, VkDeviceSize o) { return r.offset < o; });
  it = b.free.insert(it, {al.offset, al.size});
  if (auto next = it + 1; next != b.free.end() && it->offset + it->size == next->offset) {
    it->size += next->size;
    b.free.erase(next);
  }
  if (it != b.free.begin()) {
    auto prev = it - 1;
    if (prev->offset + prev->size == it->offset) {
      prev->size += it->size;
      b.free.erase(it);
    }
  }
  b.used -= al.size;
  a.used -= al.size;
  if (b.used == 0) {  // the last resource in it: give the block back
    if (!a.simulate) d.fn.vkFreeMemory(d.device, b.memory, d.allocator);
    a.held -= b.size;
    a.allocations--;
    b = MemoryArena::Block{};
  }
  al = Allocation{};
}

void destroyArena(Device& d) {
  for (MemoryArena::Block& b : d.memory.blocks)
    if (b.memory && !d.memory.simulate) d.fn.vkFreeMemory(d.device, b.memory, d.allocator);
  d.memory.blocks.clear();
  d.memory.held = d.memory.used = 0;
  d.memory.allocations = 0;
}

}  // namespace gi::vk
