// What the GI module needs of a Vulkan device, as data: the features (with
// the feature struct each lives in) and the extensions, for the engine to
// enable when it creates its device, and for gi::create to check.
// Header-only and needs only <vulkan/vulkan_core.h>.
//
//   VkPhysicalDeviceVulkan13Features f13{...};
//   VkPhysicalDeviceVulkan12Features f12{...}; f12.pNext = &f13;
//   VkPhysicalDeviceFeatures2 f2{...};         f2.pNext = &f12;   // + ray-query structs for that traversal
//   if (const char* missing = gi::enableRequiredFeatures(f2, rayQuery)) ... // a struct the chain lacks
//   extensions: gi::requiredExtensions(rayQuery) (none for the compute traversal)
// `rayQuery`: whether the scene is traced with ray queries (SceneDesc::traversal
// is Traversal::RayQuery); the compute traversal needs none of their features.
#pragma once
#include <vulkan/vulkan_core.h>

#include <cstddef>
#include <cstdint>
#include <span>

namespace gi {

struct DeviceFeature {
  const char* name;       // the VkBool32 member's name
  VkStructureType sType;  // the struct it lives in
  size_t offset;          // of the VkBool32 within that struct
  bool rayQueryOnly;      // needed only by the ray-query traversal
};

inline constexpr DeviceFeature kRequiredFeatures[] = {
    {"shaderInt64", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
     offsetof(VkPhysicalDeviceFeatures2, features.shaderInt64), false},
    {"shaderStorageImageWriteWithoutFormat", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
     offsetof(VkPhysicalDeviceFeatures2, features.shaderStorageImageWriteWithoutFormat), false},
    // The outputs are half or single floats as the engine picks, read and written without a format qualifier.
    {"shaderStorageImageReadWithoutFormat", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
     offsetof(VkPhysicalDeviceFeatures2, features.shaderStorageImageReadWithoutFormat), false},
    {"scalarBlockLayout", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, scalarBlockLayout), false},
    {"shaderBufferInt64Atomics", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, shaderBufferInt64Atomics), false},
    {"runtimeDescriptorArray", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, runtimeDescriptorArray), false},
    {"descriptorBindingPartiallyBound", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, descriptorBindingPartiallyBound), false},
    {"descriptorBindingVariableDescriptorCount", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, descriptorBindingVariableDescriptorCount), false},
    {"shaderSampledImageArrayNonUniformIndexing", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, shaderSampledImageArrayNonUniformIndexing), false},
    {"hostQueryReset", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, hostQueryReset), false},
    {"synchronization2", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
     offsetof(VkPhysicalDeviceVulkan13Features, synchronization2), false},
    // Acceleration-structure inputs, and the engine's device meshes (gi/scene.h), are read through device addresses.
    {"bufferDeviceAddress", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
     offsetof(VkPhysicalDeviceVulkan12Features, bufferDeviceAddress), false},
    {"accelerationStructure", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR,
     offsetof(VkPhysicalDeviceAccelerationStructureFeaturesKHR, accelerationStructure), true},
    {"rayQuery", VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR,
     offsetof(VkPhysicalDeviceRayQueryFeaturesKHR, rayQuery), true},
};

inline constexpr const char* kRayQueryExtensions[] = {
    VK_KHR_RAY_QUERY_EXTENSION_NAME,
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};

// Subgroup operations the module's compute shaders use, as Vulkan 1.1's
// VkPhysicalDeviceVulkan11Properties reports them: basic, arithmetic
// (counters sum over a subgroup) and vote (the path programs keep a
// subgroup's lanes in step), in compute shaders. The name of the first one
// the device lacks, or null.
inline const char* firstMissingSubgroupSupport(VkShaderStageFlags supportedStages,
                                               VkSubgroupFeatureFlags supportedOperations) {
  if (!(supportedStages & VK_SHADER_STAGE_COMPUTE_BIT)) return "subgroup operations in compute shaders";
  if (!(supportedOperations & VK_SUBGROUP_FEATURE_BASIC_BIT)) return "basic subgroup operations";
  if (!(supportedOperations & VK_SUBGROUP_FEATURE_VOTE_BIT)) return "subgroup vote operations";
  if (!(supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT)) return "subgroup arithmetic operations";
  return nullptr;
}

// The device extensions the module needs (none for the compute traversal).
inline std::span<const char* const> requiredExtensions(bool rayQuery) {
  return rayQuery ? std::span<const char* const>(kRayQueryExtensions) : std::span<const char* const>();
}

inline bool featureApplies(const DeviceFeature& f, bool rayQuery) { return !f.rayQueryOnly || rayQuery; }

// The feature's VkBool32 in a pNext chain starting at `chain`, or null when
// the chain has no struct of its type.
inline const VkBool32* findFeature(const VkPhysicalDeviceFeatures2& chain, const DeviceFeature& f) {
  for (const VkBaseInStructure* s = reinterpret_cast<const VkBaseInStructure*>(&chain); s; s = s->pNext)
    if (s->sType == f.sType) return reinterpret_cast<const VkBool32*>(reinterpret_cast<const char*>(s) + f.offset);
  return nullptr;
}

// Sets every feature the module needs in the engine's chain.
// Returns null, or the name of the first feature whose struct the chain lacks.
inline const char* enableRequiredFeatures(VkPhysicalDeviceFeatures2& chain, bool rayQuery) {
  for (const DeviceFeature& f : kRequiredFeatures) {
    if (!featureApplies(f, rayQuery)) continue;
    VkBool32* field = const_cast<VkBool32*>(findFeature(chain, f));
    if (!field) return f.name;
    *field = VK_TRUE;
  }
  return nullptr;
}

// The name of the first feature `chain` (supported or enabled features) does
// not have, or null when it has them all.
inline const char* firstMissingFeature(const VkPhysicalDeviceFeatures2& chain, bool rayQuery) {
  for (const DeviceFeature& f : kRequiredFeatures) {
    if (!featureApplies(f, rayQuery)) continue;
    const VkBool32* field = findFeature(chain, f);
    if (!field || !*field) return f.name;
  }
  return nullptr;
}

}  // namespace gi
