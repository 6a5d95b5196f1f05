// Interface of the reference path tracer (path_trace.comp): set 1 bindings and
// push constants. Accumulation images hold running sums over samples; the
// host divides by the sample count when it reads them back.
#ifndef GI_PATH_TRACER_H
#define GI_PATH_TRACER_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST PT_BINDING_CAMERA = 0;        // uniform GpuCamera
GPU_CONST PT_BINDING_FINAL = 1;         // rgba32f: Σ final radiance (direct + indirect)
GPU_CONST PT_BINDING_DIRECT = 2;        // rgba32f: Σ emission seen + light reflected once (B = 0 part)
GPU_CONST PT_BINDING_INDIRECT = 3;      // rgba32f: Σ demodulated indirect (incoming indirect radiance × cos/π at the first hit)
GPU_CONST PT_BINDING_ALBEDO_DEPTH = 4;  // rgba32f: Σ first-hit base colour (rgb) and view-space depth in metres (a)
GPU_CONST PT_BINDING_NORMAL = 5;        // rgba32f: Σ first-hit world normal (xyz), facing the camera
GPU_CONST PT_BINDING_RAY_COUNTER = 6;   // uint[1]: rays traced, added to by every dispatch
#define PT_GROUP_SIZE 8u                 // 8×8 threads per group (a macro: a const would need LocalSizeId)

struct PathTracerPush {
  uint seed;              // any value; the same seed gives the same image
  uint firstSample;       // index of the first sample of this dispatch; 0 overwrites the sums
  uint samplesPerDispatch;// samples per pixel added by this dispatch, ≥ 1
  uint maxBounces;        // B: indirect bounces (0 = direct light only)
  uint pixelJitter;       // 1 = box-filtered antialiasing, 0 = rays through pixel centres
  uint russianRouletteStart; // first bounce at which paths may be terminated (unbiased)
  uint pad0;
  uint pad1;
};
GPU_ASSERT_SIZE(PathTracerPush, 32);

GPU_NAMESPACE_END
#endif
