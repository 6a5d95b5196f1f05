// The G-buffer raster pass (dynamic rendering). Its images are colour
// attachments while it runs and storage images (GENERAL layout) after it, so
// compute passes read them with imageLoad. Contract: shaders/shared/gbuffer.h.
#pragma once
#include "gpu_timer.h"
#include "resources.h"
#include "scene_gpu.h"

#include "gi/gi.h"
#include "shared/gbuffer.h"

namespace engine {

inline constexpr VkFormat kGBufferFormats[gpu::GBUFFER_COLOR_COUNT] = {
    VK_FORMAT_R16G16B16A16_SFLOAT,  // normal
    VK_FORMAT_R8G8B8A8_UNORM,       // albedo
    VK_FORMAT_R8G8_UNORM,           // roughness, metallic
    VK_FORMAT_R32G32B32A32_SFLOAT,  // emission
    VK_FORMAT_R16G16_SFLOAT,        // motion
    VK_FORMAT_R32_SFLOAT,           // view z
};
inline constexpr VkFormat kGBufferDepthFormat = VK_FORMAT_D32_SFLOAT;

struct GBuffer {
  Image color[gpu::GBUFFER_COLOR_COUNT];
  Image depth;
  VkExtent2D extent{};        // the images' size
  VkExtent2D renderExtent{};  // the rectangle recordGBuffer renders into (from the top left; dynamic resolution)
};

struct GBufferPass {
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  DescriptorSet cameraSet;
  Buffer cameraBuffer;  // GpuCamera, written by recordGBuffer in the command buffer
};

// This G-buffer as the GI module reads it (gi::ModuleDesc::gbuffer): the module's default formats and
// encodings, the glossy flag in albedo alpha (gbuffer.frag writes the material's flag there).
gi::GBufferDesc moduleGBufferDesc();

// Errors as in vk.h: an empty G-buffer (or pass) and `error`.
GBuffer createGBuffer(const Context& ctx, VkExtent2D extent, std::string& error);
void destroyGBuffer(const Context& ctx, GBuffer& gbuffer);

GBufferPass createGBufferPass(const Context& ctx, const SceneGpu& scene, std::string& error);
void destroyGBufferPass(const Context& ctx, GBufferPass& pass);

// Writes `camera` to the pass's uniform buffer and records the raster pass.
// On return every G-buffer image is in GENERAL layout and visible to compute.
void recordGBuffer(const Context& ctx, VkCommandBuffer cmd, GBufferPass& pass, const Scene& scene,
                   const SceneGpu& sceneGpu, const GBuffer& gbuffer, const gpu::GpuCamera& camera, GpuTimer* timer);

}  // namespace engine
