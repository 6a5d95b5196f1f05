// Set 0 of the screen-space filters (shared/gi_filters.h).
#ifndef GI_FILTERS_GLSL
#define GI_FILTERS_GLSL
#extension GL_EXT_scalar_block_layout : require
#include "shared/gi_filters.h"

layout(set = 0, binding = FILTER_BINDING_GUIDANCE, rgba32f) uniform image2D filterGuidance;
layout(set = 0, binding = FILTER_BINDING_POSITION, rgba32f) uniform image2D filterPosition;
layout(set = 0, binding = FILTER_BINDING_INPUT, rgba32f) uniform image2D filterInput;
layout(set = 0, binding = FILTER_BINDING_OUTPUT, rgba32f) uniform image2D filterOutput;
layout(set = 0, binding = FILTER_BINDING_A, rgba32f) uniform image2D filterA[FILTER_STACK];
layout(set = 0, binding = FILTER_BINDING_B, rgba32f) uniform image2D filterB[FILTER_STACK];
layout(set = 0, binding = FILTER_BINDING_TEMP, rgba32f) uniform image2D filterTemp;
layout(set = 0, binding = FILTER_BINDING_PARAMS, rgba32f) uniform image2D filterParams;

ivec2 filterSize() { return imageSize(filterInput); }

#endif
