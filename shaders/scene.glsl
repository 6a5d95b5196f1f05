// Set 0: the scene (shaders/shared/gpu_scene.h), plus fetch helpers.
// Define SCENE_NO_TLAS before including in raster stages.
#ifndef GI_SCENE_GLSL
#define GI_SCENE_GLSL
#include "common.glsl"
#include "shared/gpu_scene.h"

#if !defined(SCENE_NO_TLAS) && !defined(GI_TRACE_COMPUTE)
#extension GL_EXT_ray_query : require
layout(set = 0, binding = SCENE_BINDING_TLAS) uniform accelerationStructureEXT sceneTlas;
#endif
#if !defined(SCENE_NO_TLAS) && defined(GI_TRACE_COMPUTE)
#include "shared/gpu_bvh.h"
// Texel buffers (16-byte rows of the structs), read by trace_bvh.glsl
// (textureBuffer, not samplerBuffer: SPIR-V wants no sampler on a buffer).
#extension GL_EXT_samplerless_texture_functions : require
layout(set = 0, binding = SCENE_BINDING_BVH_NODES) uniform utextureBuffer sceneBvhNodes;
layout(set = 0, binding = SCENE_BINDING_BVH_TRIANGLES) uniform utextureBuffer sceneBvhTriangles;
layout(set = 0, binding = SCENE_BINDING_BVH_TOP_NODES) uniform utextureBuffer sceneBvhTopNodes;
layout(set = 0, binding = SCENE_BINDING_BVH_INSTANCES) uniform utextureBuffer sceneBvhInstances;
#endif
// What the scene contains, as specialisation constants (SCENE_SPEC_* in
// shared/gpu_scene.h), so passes compile without the work a scene cannot need.
layout(constant_id = SCENE_SPEC_HAS_EMISSIVE) const bool GI_SCENE_HAS_EMISSIVE = true;
layout(constant_id = SCENE_SPEC_HAS_PUNCTUAL) const bool GI_SCENE_HAS_PUNCTUAL = true;
layout(constant_id = SCENE_SPEC_HAS_ALPHA_MASK) const bool GI_SCENE_HAS_ALPHA_MASK = true;
layout(constant_id = SCENE_SPEC_HAS_SKY) const bool GI_SCENE_HAS_SKY = true;

layout(set = 0, binding = SCENE_BINDING_POSITIONS, scalar) readonly buffer ScenePositions { vec3 scenePositions[]; };
layout(set = 0, binding = SCENE_BINDING_NORMALS, scalar) readonly buffer SceneNormals { vec3 sceneNormals[]; };
layout(set = 0, binding = SCENE_BINDING_UVS, scalar) readonly buffer SceneUvs { vec2 sceneUvs[]; };
layout(set = 0, binding = SCENE_BINDING_INDICES, scalar) readonly buffer SceneIndices { uint sceneIndices[]; };
layout(set = 0, binding = SCENE_BINDING_GEOMETRIES, scalar) readonly buffer SceneGeometries { GpuGeometry sceneGeometries[]; };
layout(set = 0, binding = SCENE_BINDING_INSTANCES, scalar) readonly buffer SceneInstances { GpuInstance sceneInstances[]; };
layout(set = 0, binding = SCENE_BINDING_MATERIALS, scalar) readonly buffer SceneMaterials { GpuMaterial sceneMaterials[]; };
layout(set = 0, binding = SCENE_BINDING_EMISSIVE_TRIANGLES, scalar) readonly buffer SceneEmissive { GpuEmissiveTriangle sceneEmissiveTriangles[]; };
layout(set = 0, binding = SCENE_BINDING_PUNCTUAL_LIGHTS, scalar) readonly buffer ScenePunctual { GpuPunctualLight scenePunctualLights[]; };
layout(set = 0, binding = SCENE_BINDING_CONSTANTS, scalar) uniform SceneConstantsBlock { GpuSceneConstants sceneConstants; };
layout(set = 0, binding = SCENE_BINDING_TEXTURES) uniform sampler2D sceneTextures[];

// Absolute vertex indices of one triangle.
uvec3 sceneTriangle(uint geometry, uint triangle) {
  GpuGeometry g = sceneGeometries[geometry];
  uint base = g.firstIndex + 3u * triangle;
  return uvec3(sceneIndices[base], sceneIndices[base + 1u], sceneIndices[base + 2u]) + g.vertexOffset;
}

vec3 giBarycentricWeights(vec2 bary) { return vec3(1.0 - bary.x - bary.y, bary.x, bary.y); }

vec2 sceneUv(uvec3 tri, vec3 w) { return sceneUvs[tri.x] * w.x + sceneUvs[tri.y] * w.y + sceneUvs[tri.z] * w.z; }

// Texture reads: fragment stages use implicit derivatives (mips), ray-traced
// stages read the top level, since a ray hit has no screen footprint.
vec4 sceneTexture(uint index, vec2 uv) {
#ifdef SCENE_IMPLICIT_LOD
  return texture(sceneTextures[nonuniformEXT(index)], uv);
#else
  return textureLod(sceneTextures[nonuniformEXT(index)], uv, 0.0);
#endif
}

struct MaterialSample {
  vec3 baseColor;  // linear
  float alpha;
  float metallic;
  float roughness;
  vec3 emission;   // W/(sr·m²), before the one-sidedness test
  uint flags;
};

MaterialSample sceneMaterial(uint materialIndex, vec2 uv) {
  GpuMaterial m = sceneMaterials[materialIndex];
  MaterialSample s;
  vec4 base = m.baseColor;
  if (m.baseColorTexture != NO_TEXTURE) base *= sceneTexture(m.baseColorTexture, uv);
  s.baseColor = base.rgb;
  s.alpha = base.a;
  s.metallic = m.metallic;
  s.roughness = m.roughness;
  if (m.metallicRoughnessTexture != NO_TEXTURE) {
    vec4 mr = sceneTexture(m.metallicRoughnessTexture, uv);
    s.roughness *= mr.g;
    s.metallic *= mr.b;
  }
  s.emission = m.emission;
  if (m.emissiveTexture != NO_TEXTURE) s.emission *= sceneTexture(m.emissiveTexture, uv).rgb;
  s.flags = m.flags;
  return s;
}

#endif
