#version 460
// G-buffer raster, fragment stage: material evaluation shared with the ray
// tracer (scene.glsl), alpha-mask discard, and the G-buffer contract in
// shared/gbuffer.h. Both faces are drawn; the normal is turned to the camera.
#extension GL_GOOGLE_include_directive : require
#define SCENE_NO_TLAS
#define SCENE_IMPLICIT_LOD
#include "scene.glsl"
#include "camera.glsl"
#include "shared/gbuffer.h"
// The engine's program: its reads are never checked (bounds.glsl).
GI_BOUNDS_UNCHECKED

layout(set = 1, binding = GBUFFER_BINDING_CAMERA, scalar) uniform CameraBlock { GpuCamera camera; };
layout(push_constant, scalar) uniform Push { GBufferPush pc; };

layout(location = 0) in vec3 inWorldPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inPreviousClip;
layout(location = 4) in vec4 inClip;

layout(location = GBUFFER_NORMAL) out vec4 outNormal;
layout(location = GBUFFER_ALBEDO) out vec4 outAlbedo;
layout(location = GBUFFER_MATERIAL) out vec2 outMaterial;
layout(location = GBUFFER_EMISSION) out vec4 outEmission;
layout(location = GBUFFER_MOTION) out vec2 outMotion;
layout(location = GBUFFER_VIEWZ) out float outViewZ;

void main() {
  const uint material = sceneGeometry(pc.geometry).material;
  MaterialSample m = sceneMaterial(material, inUv);
  if ((m.flags & MATERIAL_FLAG_ALPHA_MASK) != 0u && m.alpha < sceneMaterialData(material).alphaCutoff)
    discard;
  // Orientation as in surface.glsl: the triangle normal, agreeing with the
  // interpolated normal, decides the emitting side; shading faces the camera.
  vec3 dpdx = dFdx(inWorldPosition), dpdy = dFdy(inWorldPosition);
  vec3 geometric = cross(dpdy, dpdx);
  float gl = length(geometric);
  float nl = length(inNormal);
  vec3 n = nl > 0.0 ? inNormal / nl : (gl > 0.0 ? geometric / gl : vec3(0.0, 1.0, 0.0));
  geometric = gl > 0.0 ? geometric / gl : n;
  if (dot(geometric, n) < 0.0) geometric = -geometric;
  vec3 toCamera = camera.position - inWorldPosition;
  bool front = dot(geometric, toCamera) > 0.0;
  if (!front) n = -n;
  if (dot(n, toCamera) < 0.0) n = front ? geometric : -geometric;

  outNormal = vec4(n, 1.0);
  outAlbedo = vec4(m.baseColor, (m.flags & MATERIAL_FLAG_GLOSSY) != 0u ? 1.0 : 0.0);
  outMaterial = vec2(m.roughness, m.metallic);
  outEmission = vec4(front ? m.emission : vec3(0.0), 1.0);
  vec2 current = inClip.xy / inClip.w;
  vec2 previous = inPreviousClip.xy / inPreviousClip.w;
  outMotion = (previous - current) * 0.5 * camera.imageSize;
  outViewZ = giViewDepth(camera, inWorldPosition);
}
