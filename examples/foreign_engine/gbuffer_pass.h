// The foreign engine's G-buffer: five colour targets and a reversed-Z depth
// buffer in the formats it declares to the module (kGBufferDesc), drawn from
// its own vertex and index buffers with dynamic rendering.
#pragma once
#include <glm/glm.hpp>

#include <gi/gi.h>

#include <vector>

#include "gltf_scene.h"
#include "vulkan_host.h"

namespace foreign {

enum Target : uint32_t { kNormal, kAlbedo, kMaterial, kEmission, kMotion, kTargetCount };
inline constexpr VkFormat kTargetFormats[kTargetCount] = {VK_FORMAT_R16G16_UNORM, VK_FORMAT_R8G8B8A8_SRGB,
                                                          VK_FORMAT_R8G8_UNORM, VK_FORMAT_R16G16B16A16_SFLOAT,
                                                          VK_FORMAT_R16G16_SFLOAT};
inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

// What the module is told about this G-buffer.
gi::GBufferDesc gbufferDesc();

struct FrameUniforms {  // gbuffer.vert's Frame block (std140)
  glm::mat4 clipFromWorld, motionClipFromWorld, previousClipFromWorld;
  glm::vec4 cameraPosition, imageSize;
};

struct Draw {
  uint32_t firstIndex, indexCount;
  int32_t vertexOffset;
  uint32_t material;
  glm::mat4 worldFromObject;
};

// Where a mesh of the scene file lies in the pass's vertex and index buffers.
struct MeshRange {
  uint32_t firstVertex = 0, vertexCount = 0, firstIndex = 0, indexCount = 0;
  std::vector<gi::PrimitiveDesc> primitives;  // firstIndex counts from the range's first index
};

// Frames the example records ahead of the GPU (gi::ModuleDesc::framesInFlight): each has its own
// command buffer, fence, uniforms and readback buffer, and waits only on the fence of the frame this
// many back.
inline constexpr uint32_t kFramesInFlight = 3;

struct GBufferPass {
  VkExtent2D extent{};
  example::Image targets[kTargetCount];
  example::Image depth;
  example::Buffer vertices, indices;  // interleaved position, normal; uint32 (with device addresses)
  std::vector<MeshRange> meshes;      // per mesh of the scene file
  std::vector<Draw> draws;
  std::vector<gi::MaterialDesc> materials;
  example::Buffer uniforms[kFramesInFlight];  // per frame slot
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkDescriptorPool descriptorPool = VK_NULL_HANDLE;
  VkDescriptorSet sets[kFramesInFlight]{};
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  bool initialised = false;  // targets left in their sampled layouts at least once
};

void createGBufferPass(const example::Host& h, const SceneFile& scene, VkExtent2D extent, GBufferPass& pass);
void destroyGBufferPass(const example::Host& h, GBufferPass& pass);
// Rasterises the scene; leaves every target (depth included) in SHADER_READ_ONLY_OPTIMAL, made visible
// to compute-shader sampled reads.
void recordGBuffer(VkCommandBuffer cmd, GBufferPass& pass, uint32_t slot, const FrameUniforms& uniforms);
gi::GBufferViews gbufferViews(const GBufferPass& pass);
// The pass's own vertex and index buffers, as the module's device meshes
// (positions and normals interleaved, stride 24; uint32 indices).
std::vector<gi::MeshDesc> deviceMeshes(const example::Host& h, const GBufferPass& pass);

}  // namespace foreign
