#version 460
// The foreign engine's G-buffer raster: its own vertex buffer (position,
// normal) and a jittered, reversed-Z projection.
layout(set = 0, binding = 0) uniform Frame {
  mat4 clipFromWorld;          // jittered: what the rasteriser uses
  mat4 motionClipFromWorld;    // unjittered, this frame
  mat4 previousClipFromWorld;  // unjittered, last frame
  vec4 cameraPosition;
  vec4 imageSize;
} frame;
layout(push_constant) uniform Draw {
  mat4 worldFromObject;
  vec4 baseColor;
  vec4 emissionRoughness;  // rgb emission (W/(sr·m²)), a roughness
  vec4 metallic;           // x
} draw;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec3 outWorld;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec4 outMotionClip;
layout(location = 3) out vec4 outPreviousClip;

void main() {
  vec4 world = draw.worldFromObject * vec4(inPosition, 1.0);
  outWorld = world.xyz;
  outNormal = transpose(inverse(mat3(draw.worldFromObject))) * inNormal;
  outMotionClip = frame.motionClipFromWorld * world;
  outPreviousClip = frame.previousClipFromWorld * world;  // static geometry: last frame's position is this one
  gl_Position = frame.clipFromWorld * world;
}
