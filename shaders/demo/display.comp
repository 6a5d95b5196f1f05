#version 460
// Exposure, clamp and nearest-pixel scaling from linear radiance to the
// display image (still linear: the swapchain's sRGB format, or the PNG
// writer, encodes it).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_image_load_formatted : require
#include "shared/display.h"

layout(local_size_x = DISPLAY_GROUP_SIZE, local_size_y = DISPLAY_GROUP_SIZE) in;
layout(set = 0, binding = DISPLAY_BINDING_SOURCE) uniform readonly image2D source;  // the module's output format
layout(set = 0, binding = DISPLAY_BINDING_TARGET, rgba16f) uniform writeonly image2D target;
layout(push_constant, scalar) uniform Push { DisplayPush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(target)))) return;
  // Nearest source pixel of the render rectangle: the display may be larger or smaller.
  ivec2 q = ivec2((vec2(p) + 0.5) * vec2(pc.sourceSize) / vec2(imageSize(target)));
  vec3 c = imageLoad(source, q).rgb * pc.exposure;
  c = clamp(c, vec3(0.0), vec3(1.0));  // NaN-safe enough: the module never emits non-finite values
  imageStore(target, p, vec4(c, 1.0));
}
