#version 460
// G-buffer raster, vertex stage: pulls vertices from the scene's texel
// buffers (no vertex input state), one draw per (instance, geometry).
#extension GL_GOOGLE_include_directive : require
#define SCENE_NO_TLAS
#include "scene.glsl"
#include "shared/gbuffer.h"
// The engine's program: its reads are never checked (bounds.glsl).
GI_BOUNDS_UNCHECKED

layout(set = 1, binding = GBUFFER_BINDING_CAMERA, scalar) uniform CameraBlock { GpuCamera camera; };
layout(push_constant, scalar) uniform Push { GBufferPush pc; };

layout(location = 0) out vec3 outWorldPosition;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;
layout(location = 3) out vec4 outPreviousClip;
layout(location = 4) out vec4 outClip;

void main() {
  GpuGeometry g = sceneGeometry(pc.geometry);
  uint vertex = sceneIndex(g.firstIndex + uint(gl_VertexIndex)) + g.vertexOffset;
  GpuInstance inst = sceneInstance(pc.instance);
  vec3 position = scenePosition(vertex);
  vec4 world = inst.worldFromObject * vec4(position, 1.0);
  outWorldPosition = world.xyz;
  outNormal = mat3(inst.normalWorldFromObject) * sceneNormal(vertex);
  outUv = sceneUvAt(vertex);
  // Motion: the previous transform of the previous position (a deforming mesh's last pose).
  outPreviousClip = camera.previousClipFromWorld * (inst.previousWorldFromObject * vec4(scenePreviousPosition(vertex), 1.0));
  outClip = camera.clipFromWorld * world;
  gl_Position = outClip;
}
