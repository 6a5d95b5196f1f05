// gi::ModuleDesc::checkBounds: the bounds-checked variant of the module's
// programs. Every index into the hash map's arrays (hpsf.glsl's HG_AT) and
// every coordinate of the images of set 1 and of the screen filters' set
// (gi_frame.glsl's and filters.glsl's imageLoad and imageStore) and every
// index into the scene's texel buffers (GI_FETCH) is checked against the
// size of what it reads or writes; one
// outside is counted (HgTelemetry::outOfBounds, GiCounters::boundsViolations:
// FrameStats::boundsViolations) and replaced by the first element, so the
// access stays inside. On lavapipe the device's memory is the host's heap: an
// access outside a buffer corrupts whatever lies beside it. Off (the
// default), the checks are specialised away.
#ifndef GI_BOUNDS_GLSL
#define GI_BOUNDS_GLSL
#include "shared/gi_frame.h"

layout(constant_id = GI_SPEC_CHECK_BOUNDS) const bool GI_CHECK_BOUNDS = false;

// Image accesses: a set with a counter defines giCheckedPixel with this, counting into it, before its
// first image access (gi_frame.glsl, filters.glsl); every imageLoad and imageStore after goes through it.
#define GI_COUNT_PIXELS_OUTSIDE_INTO(counter)                                                        \
  ivec2 giCheckedPixel(ivec2 p, ivec2 size) {                                                       \
    if (!(GI_CHECK_BOUNDS && (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))))) return p; \
    atomicAdd(counter, 1u);                                                                         \
    return ivec2(0);                                                                                \
  }
#define imageLoad(image, p) imageLoad(image, giCheckedPixel(p, imageSize(image)))
#define imageStore(image, p, v) imageStore(image, giCheckedPixel(p, imageSize(image)), v)

// The scene's texel buffers (scene.glsl, trace_bvh.glsl, sky.glsl read them through GI_FETCH): every
// program that reads them defines giCheckedTexel once, counting where it has a counter (gi_frame.glsl)
// and passing the index through where it has none (the engine's programs: GI_BOUNDS_UNCHECKED).
int giCheckedTexel(int i, int size);
#define GI_FETCH(buffer, i) texelFetch(buffer, giCheckedTexel(int(i), textureSize(buffer)))
#define GI_COUNT_TEXELS_OUTSIDE_INTO(counter)                 \
  int giCheckedTexel(int i, int size) {                       \
    if (!(GI_CHECK_BOUNDS && (i < 0 || i >= size))) return i; \
    atomicAdd(counter, 1u);                                   \
    return 0;                                                 \
  }
// The engine's programs (no counter, never checked): the accessors as plain reads.
#define GI_BOUNDS_UNCHECKED                                      \
  int giCheckedTexel(int i, int size) { return i; }              \
  ivec2 giCheckedPixel(ivec2 p, ivec2 size) { return p; }

#endif
