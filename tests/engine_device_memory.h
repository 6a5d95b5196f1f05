// A test host's device-memory allocator (gi::DeviceMemoryCallbacks) that counts every byte it hands
// the module or a scene, and a loader entry point that counts the module's own vkAllocateMemory,
// vkCreateImage and vkCreateBuffer calls.
// Each request gets its own VkDeviceMemory with the slice placed one alignment in, so a module that
// ignored the offset would bind the wrong bytes.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>

#include <gtest/gtest.h>

#include "context.h"
#include "resources.h"
#include "gi/device_memory.h"

struct EngineDeviceMemory {
  const engine::Context* ctx = nullptr;
  uint64_t liveBytes = 0, transientBytes = 0;  // requested sizes of the slices alive
  uint32_t requests = 0, frees = 0;
  std::map<VkDeviceMemory, gi::DeviceMemoryRequest> live;
  std::string error;  // a free of a slice this allocator did not hand out

  explicit EngineDeviceMemory(const engine::Context& c) : ctx(&c) {}
  ~EngineDeviceMemory() {
    for (const auto& [memory, request] : live) vkFreeMemory(ctx->device, memory, nullptr);
  }

  gi::DeviceMemoryCallbacks callbacks() {
    gi::DeviceMemoryCallbacks c;
    c.userData = this;
    c.allocate = [](void* user, const gi::DeviceMemoryRequest& r, gi::DeviceMemorySlice& out) {
      return static_cast<EngineDeviceMemory*>(user)->allocate(r, out);
    };
    c.free = [](void* user, const gi::DeviceMemorySlice& slice) {
      static_cast<EngineDeviceMemory*>(user)->release(slice);
    };
    return c;
  }

  VkResult allocate(const gi::DeviceMemoryRequest& r, gi::DeviceMemorySlice& out) {
    uint32_t type = 0;
    if (std::string noType; !engine::findMemoryType(*ctx, r.requirements.memoryTypeBits, r.properties, type, noType))
      return VK_ERROR_OUT_OF_DEVICE_MEMORY;  // the module names the failed allocation
    const VkDeviceSize alignment = std::max<VkDeviceSize>(r.requirements.alignment, 1);
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = r.allocateFlags;
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.pNext = r.allocateFlags ? &flags : nullptr;
    info.allocationSize = alignment + r.requirements.size;
    info.memoryTypeIndex = type;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    if (VkResult result = vkAllocateMemory(ctx->device, &info, nullptr, &memory); result != VK_SUCCESS) return result;
    out.memory = memory;
    out.offset = alignment;
    out.mapped = nullptr;
    if (r.properties & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
      void* base = nullptr;
      vkMapMemory(ctx->device, memory, 0, VK_WHOLE_SIZE, 0, &base);
      out.mapped = static_cast<char*>(base) + alignment;
    }
    live[memory] = r;
    liveBytes += r.requirements.size;
    if (r.transient) transientBytes += r.requirements.size;
    requests++;
    return VK_SUCCESS;
  }

  void release(const gi::DeviceMemorySlice& slice) {
    auto it = live.find(slice.memory);
    if (it == live.end() || slice.size != it->second.requirements.size) {
      if (error.empty()) error = "a free of a slice this allocator did not hand out (or of another size)";
      return;
    }
    liveBytes -= it->second.requirements.size;
    if (it->second.transient) transientBytes -= it->second.requirements.size;
    vkFreeMemory(ctx->device, slice.memory, nullptr);
    live.erase(it);
    frees++;
  }
};

// vkGetInstanceProcAddr (volk's), but vkAllocateMemory, vkCreateImage and vkCreateBuffer are counted: a
// module or scene created with it calls them through the counters (it loads its device functions
// through the vkGetDeviceProcAddr this returns).
inline std::atomic<uint32_t> moduleAllocateMemoryCalls{0}, moduleCreateImageCalls{0}, moduleCreateBufferCalls{0};
inline VKAPI_ATTR VkResult VKAPI_CALL countedAllocateMemory(VkDevice device, const VkMemoryAllocateInfo* info,
                                                            const VkAllocationCallbacks* allocator,
                                                            VkDeviceMemory* out) {
  moduleAllocateMemoryCalls++;
  return vkAllocateMemory(device, info, allocator, out);
}
inline VKAPI_ATTR VkResult VKAPI_CALL countedCreateImage(VkDevice device, const VkImageCreateInfo* info,
                                                         const VkAllocationCallbacks* allocator, VkImage* out) {
  moduleCreateImageCalls++;
  return vkCreateImage(device, info, allocator, out);
}
inline VKAPI_ATTR VkResult VKAPI_CALL countedCreateBuffer(VkDevice device, const VkBufferCreateInfo* info,
                                                          const VkAllocationCallbacks* allocator, VkBuffer* out) {
  moduleCreateBufferCalls++;
  return vkCreateBuffer(device, info, allocator, out);
}
inline PFN_vkVoidFunction countedDeviceFunction(const char* name) {
  if (std::strcmp(name, "vkAllocateMemory") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&countedAllocateMemory);
  if (std::strcmp(name, "vkCreateImage") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&countedCreateImage);
  if (std::strcmp(name, "vkCreateBuffer") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&countedCreateBuffer);
  return nullptr;
}
inline VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countingGetDeviceProcAddr(VkDevice device, const char* name) {
  if (PFN_vkVoidFunction counted = countedDeviceFunction(name)) return counted;
  return vkGetDeviceProcAddr(device, name);
}
inline VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countingGetInstanceProcAddr(VkInstance instance, const char* name) {
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&countingGetDeviceProcAddr);
  if (PFN_vkVoidFunction counted = countedDeviceFunction(name)) return counted;
  return vkGetInstanceProcAddr(instance, name);
}

// A transient pool: the transient requests of a module carved one after another (aligned) from one
// VkDeviceMemory of `bytes` (the engine sizes it with gi::predictMemory), which a buffer of the
// engine's own aliases whole. The other requests go to `EngineDeviceMemory`.
struct AliasedTransientPool {
  EngineDeviceMemory* other = nullptr;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkBuffer alias = VK_NULL_HANDLE;  // the engine's resource on the same bytes
  VkDeviceSize size = 0, used = 0;
  uint32_t memoryType = UINT32_MAX, slices = 0;

  AliasedTransientPool(const engine::Context& ctx, EngineDeviceMemory& nonTransient, VkDeviceSize bytes)
      : other(&nonTransient) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    vkCreateBuffer(ctx.device, &info, nullptr, &alias);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device, alias, &req);
    std::string error;
    if (!engine::findMemoryType(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, memoryType, error))
      ADD_FAILURE() << error;
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = size = req.size;
    alloc.memoryTypeIndex = memoryType;
    vkAllocateMemory(ctx.device, &alloc, nullptr, &memory);
    vkBindBufferMemory(ctx.device, alias, memory, 0);
  }
  ~AliasedTransientPool() {
    vkDestroyBuffer(other->ctx->device, alias, nullptr);
    vkFreeMemory(other->ctx->device, memory, nullptr);
  }

  gi::DeviceMemoryCallbacks callbacks() {
    gi::DeviceMemoryCallbacks c;
    c.userData = this;
    c.allocate = [](void* user, const gi::DeviceMemoryRequest& r, gi::DeviceMemorySlice& out) {
      auto* pool = static_cast<AliasedTransientPool*>(user);
      if (!r.transient) return pool->other->allocate(r, out);
      const VkDeviceSize alignment = std::max<VkDeviceSize>(r.requirements.alignment, 1);
      const VkDeviceSize offset = (pool->used + alignment - 1) / alignment * alignment;
      if (!(r.requirements.memoryTypeBits & (1u << pool->memoryType)) || offset + r.requirements.size > pool->size)
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
      pool->used = offset + r.requirements.size;
      pool->slices++;
      out.memory = pool->memory;
      out.offset = offset;
      return VK_SUCCESS;
    };
    c.free = [](void* user, const gi::DeviceMemorySlice& slice) {
      auto* pool = static_cast<AliasedTransientPool*>(user);
      if (slice.memory != pool->memory) pool->other->release(slice);  // the pool's slices go with the pool
    };
    return c;
  }
};
