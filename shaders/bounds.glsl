// gi::ModuleDesc::checkBounds: the bounds-checked variant of the module's
// programs. Every index into the hash map's arrays (hpsf.glsl's HG_AT) and
// every coordinate of the images of set 1 and of the screen filters' set
// (gi_frame.glsl's and filters.glsl's imageLoad and imageStore) is checked against the size of what it reads or writes; one
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

#endif
