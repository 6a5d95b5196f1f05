#version 460
// Dear ImGui's vertices: pixel position, font-atlas uv, sRGB colour. The
// display image is linear, so the colour is linearised here.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/display.h"

layout(location = 0) in vec2 inPosition;
layout(location = 1) in vec2 inUv;
layout(location = 2) in vec4 inColor;
layout(push_constant, scalar) uniform Push { OverlayPush pc; };
layout(location = 0) out vec2 uv;
layout(location = 1) out vec4 color;

void main() {
  uv = inUv;
  color = vec4(pow(inColor.rgb, vec3(2.2)), inColor.a);
  gl_Position = vec4(inPosition * pc.scale + pc.translate, 0.0, 1.0);
}
