// The module's device memory: a few blocks, suballocated, or the engine's (gi/device_memory.h: one
// request per resource and no block of the module's). Blocks grow from 256 KiB, doubling with each live
// block of the same kind up to 64 MiB, so a small render size holds little more than it uses; resources
// of half a block or more get a block of their own size. A block is freed once its last resource is. A
// budget (bytes held, 0 = none) lets an engine cap the module: an allocation beyond it fails with
// VK_ERROR_OUT_OF_DEVICE_MEMORY like a full heap would. A simulated arena (`simulate`) runs the same
// rules without calling Vulkan or the engine: gi::predictMemory replays a module's requests through it.
#pragma once
#include <cstdint>
#include <mutex>
#include <vector>

#include "gi/device_memory.h"
#include "gi/vk/status.h"

namespace gi::vk {

struct Device;

struct Allocation {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0, size = 0;
  void* mapped = nullptr;       // host-visible allocations: mapped for their lifetime
  uint32_t block = UINT32_MAX;  // the arena's block, or kEngineMemory
};
constexpr uint32_t kEngineMemory = UINT32_MAX - 1;  // an Allocation the engine's callbacks supplied

struct MemoryArena {
  // allocate and release may run on two threads (a warm-up recorded on an
  // engine's thread while its main thread records frames): one lock guards the blocks.
  struct Lock {
    std::mutex mutex;
    Lock() = default;
    Lock(const Lock&) {}
    Lock& operator=(const Lock&) { return *this; }
  };
  struct Range {
    VkDeviceSize offset, size;
  };
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;  // null: a freed block whose slot is reusable
    VkDeviceSize size = 0, used = 0;
    uint32_t memoryType = 0;
    bool shared = false;  // suballocated (false: one resource's own block)
    bool linear = false;  // buffers and optimal-tiling images never share a block (bufferImageGranularity)
    bool hostVisible =
        false;  // mapped whole (but on a simulated arena); device-local blocks never hold host-visible resources
    void* mapped = nullptr;
    std::vector<Range> free;  // sorted by offset, neighbours merged
  };
  std::vector<Block> blocks;
  VkDeviceSize firstBlockSize = VkDeviceSize(256) << 10, maxBlockSize = VkDeviceSize(64) << 20;
  VkDeviceSize budget = 0;       // bytes the module may hold; 0: as many as the device gives
  VkDeviceSize held = 0;         // bytes allocated from the device
  VkDeviceSize used = 0;         // bytes handed to resources
  uint32_t allocations = 0;      // live vkAllocateMemory blocks
  DeviceMemoryCallbacks engine;  // set: every allocation is the engine's (held = used = what it was asked for)
  bool simulate = false;         // no Vulkan or engine call: blocks and slices get placeholder handles
  uint64_t nextPlaceholder = 1;  // simulate: the next placeholder VkDeviceMemory
  Lock lock;
};

// `linear`: a buffer (or linear image). `hostVisible`: host-visible and coherent, mapped. `transient`:
// contents live within a frame (told to the engine's callbacks).
Status allocate(Device& device, const VkMemoryRequirements& requirements, bool hostVisible, bool linear, bool transient,
                Allocation& out);
void release(Device& device, Allocation& allocation);
void destroyArena(Device& device);

}  // namespace gi::vk
