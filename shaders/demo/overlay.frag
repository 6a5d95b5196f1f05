#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "shared/display.h"

layout(set = 0, binding = OVERLAY_BINDING_FONT) uniform sampler2D font;
layout(location = 0) in vec2 uv;
layout(location = 1) in vec4 color;
layout(location = 0) out vec4 outColor;

void main() { outColor = color * texture(font, uv); }
