// The G-buffer contract, shared by the raster pass that writes it and every
// pass that reads it. Background pixels have viewZ = 0 and normal.w = 0.
#ifndef GI_GBUFFER_H
#define GI_GBUFFER_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

// Colour attachment locations (formats in engine/gbuffer.h).
GPU_CONST GBUFFER_NORMAL = 0;    // rgba16f: world shading normal facing the camera (xyz), coverage (w)
GPU_CONST GBUFFER_ALBEDO = 1;    // rgba8 unorm: linear base colour (rgb), 1 where the material has a GGX lobe (a)
GPU_CONST GBUFFER_MATERIAL = 2;  // rg8 unorm: roughness, metallic
GPU_CONST GBUFFER_EMISSION = 3;  // rgba32f: emitted radiance towards the camera, W/(sr·m²) (fp32: 1e6 must fit)
GPU_CONST GBUFFER_MOTION = 4;    // rg16f: previous pixel position − current, in pixels
GPU_CONST GBUFFER_VIEWZ = 5;     // r32f: view-space depth along −Z, metres (0 = background)
GPU_CONST GBUFFER_COLOR_COUNT = 6;

GPU_CONST GBUFFER_BINDING_CAMERA = 0;  // set 1: uniform GpuCamera

struct GBufferPush {
  uint instance;  // index into the instance table
  uint geometry;  // absolute geometry (primitive) index
};
GPU_ASSERT_SIZE(GBufferPush, 8);

GPU_NAMESPACE_END
#endif
