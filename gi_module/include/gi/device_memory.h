// Device memory the engine supplies (ModuleDesc::deviceMemory, SceneCreateDesc::deviceMemory): with
// both callbacks set, every buffer and image of the module or scene takes its memory from the engine's
// allocator (its pools, its budget, its aliasing), one request per resource, and the module calls
// vkAllocateMemory never. Without them it suballocates blocks of its own.
#pragma once
#include <vulkan/vulkan_core.h>

#include <cstdint>

namespace gi {

struct DeviceMemoryRequest {
  VkMemoryRequirements requirements;  // size, alignment and the memory types allowed, as Vulkan reports them
  // DEVICE_LOCAL, or HOST_VISIBLE | HOST_COHERENT: then the module writes it from the host through
  // DeviceMemorySlice::mapped, for as long as the resource lives.
  VkMemoryPropertyFlags properties;
  // DEVICE_ADDRESS where the module reads the resource by its device address (acceleration-structure
  // inputs and storage); the memory must have been allocated with these flags.
  VkMemoryAllocateFlags allocateFlags;
  bool linear;  // a buffer (true) or an optimal-tiling image: bufferImageGranularity keeps them apart
  // Contents live within one frame (NRD's transient pool): memory the engine may alias with its own
  // resources between the module's frames. recordFrame starts each such image from UNDEFINED after every
  // earlier command's writes; the engine's use of the memory after a frame waits for that frame's
  // compute work (a barrier of its own, as for any aliased memory).
  bool transient;
};

struct DeviceMemorySlice {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;  // a multiple of requirements.alignment
  VkDeviceSize size = 0;    // requirements.size (the module fills it)
  void* mapped = nullptr;   // host-visible requests: the host address of `offset` (the engine maps its memory)
};

struct DeviceMemoryCallbacks {
  void* userData = nullptr;
  // VK_SUCCESS and `out` (memory, offset, mapped) for `request`, or the error the module returns
  // (VK_ERROR_OUT_OF_DEVICE_MEMORY for a full pool). Called from the thread calling into the module.
  VkResult (*allocate)(void* userData, const DeviceMemoryRequest& request, DeviceMemorySlice& out) = nullptr;
  // Called once per slice the allocate callback returned, after the GPU's last use of it.
  void (*free)(void* userData, const DeviceMemorySlice& slice) = nullptr;
  bool enabled() const { return allocate != nullptr; }
};

}  // namespace gi
