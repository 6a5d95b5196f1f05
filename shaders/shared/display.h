// The demo's display passes: exposure from the module's linear composite to
// the display image, and the Dear ImGui overlay drawn on top of it.
#ifndef GI_DISPLAY_H
#define GI_DISPLAY_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST DISPLAY_BINDING_SOURCE = 0;  // storage image (rgba16f or rgba32f): the module's composite, pre-exposed
GPU_CONST DISPLAY_BINDING_TARGET = 1;  // rgba16f storage image: linear display values in [0, 1]
#define DISPLAY_GROUP_SIZE 8u

struct DisplayPush {
  float exposure;    // multiplier on the (pre-exposed) composite before clamping to [0, 1]
  uint pad0;
  uvec2 sourceSize;  // the render rectangle in the source (dynamic resolution: the image may be larger)
};
GPU_ASSERT_SIZE(DisplayPush, 16);

GPU_CONST OVERLAY_BINDING_FONT = 0;    // combined image sampler: ImGui's font atlas (rgba8 unorm)

// Maps ImGui's pixel coordinates to clip space: clip = position · scale + translate.
struct OverlayPush {
  vec2 scale;
  vec2 translate;
};
GPU_ASSERT_SIZE(OverlayPush, 16);

GPU_NAMESPACE_END
#endif
