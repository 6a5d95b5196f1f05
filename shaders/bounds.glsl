// gi::ModuleDesc::checkBounds: the bounds-checked variant of the module's
// programs. Every index into the hash map's arrays (hpsf.glsl's HG_AT) and
// every coordinate of set 1's images (gi_frame.glsl's imageLoad and
// imageStore) is checked against the size of what it reads or writes; one
// outside is counted (HgTelemetry::outOfBounds, GiCounters::boundsViolations:
// FrameStats::boundsViolations) and replaced by the first element, so the
// access stays inside. On lavapipe the device's memory is the host's heap: an
// access outside a buffer corrupts whatever lies beside it. Off (the
// default), the checks are specialised away.
#ifndef GI_BOUNDS_GLSL
#define GI_BOUNDS_GLSL
#include "shared/gi_frame.h"

layout(constant_id = GI_SPEC_CHECK_BOUNDS) const bool GI_CHECK_BOUNDS = false;

#endif
