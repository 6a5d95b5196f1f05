// Set 0 of the screen-space filters (shared/gi_filters.h).
#ifndef GI_FILTERS_GLSL
#define GI_FILTERS_GLSL
#extension GL_EXT_shader_image_load_formatted : require
#extension GL_EXT_scalar_block_layout : require
#include "bounds.glsl"
#include "shared/gi_filters.h"

// Guidance, positions, input and params are formatless: the module's are half floats, AAF's glossy terms
// (which carry their β as params do) and the tests' synthetic images single floats.
layout(set = 0, binding = FILTER_BINDING_GUIDANCE) uniform image2D filterGuidance;
layout(set = 0, binding = FILTER_BINDING_POSITION) uniform image2D filterPosition;
layout(set = 0, binding = FILTER_BINDING_INPUT) uniform image2D filterInput;
layout(set = 0, binding = FILTER_BINDING_OUTPUT) uniform image2D filterOutput;  // formatless (FilterOutputEncoding)
layout(set = 0, binding = FILTER_BINDING_A, rgba32f) uniform image2D filterA[FILTER_STACK];
layout(set = 0, binding = FILTER_BINDING_TEMP) uniform image2D filterTemp;  // formatless: half or single floats
layout(set = 0, binding = FILTER_BINDING_PARAMS) uniform image2D filterParams;
layout(set = 0, binding = FILTER_BINDING_COUNTERS, scalar) buffer FilterCountersBlock { GiCounters filterCounters; };

// With ModuleDesc::checkBounds a coordinate outside its image is counted here (bounds.glsl).
GI_COUNT_PIXELS_OUTSIDE_INTO(filterCounters.boundsViolations)

// The render rectangle: every filter's push constants (`pc`) carry it, as the images may be larger
// (dynamic resolution).
#define filterSize() ivec2(pc.size)

void filterStoreOutput(ivec2 p, vec3 radiance, FilterOutputEncoding e) {
  imageStore(filterOutput, p, vec4(clamp(radiance * e.scale, vec3(-e.limit), vec3(e.limit)), 1.0));
}
vec3 filterLoadOutput(ivec2 p, FilterOutputEncoding e) { return imageLoad(filterOutput, p).rgb / e.scale; }

// The guided filter's guidance vector for 1 (grey normal), 3 (normal) or 4
// (normal + depth) dimensions; unused channels are zero, so their
// coefficients solve to zero.
// The guided filter's statistics images over the render rectangle: one pixel per s×s pixels, rounded up.
// (A macro, as filterSize is: the push constants are declared after this file.)
#define gifStackSize(s) ((filterSize() + ivec2(int(s) - 1)) / int(s))

vec4 gifGuidance(ivec2 p, uint dimensions) {
  vec4 g = imageLoad(filterGuidance, p);
  return dimensions == 1u ? vec4((g.x + g.y + g.z) / 3.0, 0.0, 0.0, 0.0) : dimensions == 3u ? vec4(g.xyz, 0.0) : g;
}

#endif
