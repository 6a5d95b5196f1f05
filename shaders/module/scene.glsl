// Set 0: the scene (shaders/shared/gpu_scene.h), plus fetch helpers.
// Define SCENE_NO_TLAS before including in raster stages.
#ifndef GI_SCENE_GLSL
#define GI_SCENE_GLSL
#include "bounds.glsl"
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

// The scene's arrays are uniform texel buffers (gpu_scene.h): on lavapipe a
// texel fetch is one call for all lanes, where a storage-buffer load with a
// per-lane address unrolls into a bounds-checked load per lane (about 220
// lines of LLVM IR each), and a program's compile time grows faster than its size.
#extension GL_EXT_samplerless_texture_functions : require
layout(set = 0, binding = SCENE_BINDING_POSITIONS) uniform textureBuffer scenePositionTexels;     // R32_SFLOAT, 3 a vertex
layout(set = 0, binding = SCENE_BINDING_PREVIOUS_POSITIONS) uniform textureBuffer scenePreviousPositionTexels;  // R32_SFLOAT
layout(set = 0, binding = SCENE_BINDING_NORMALS) uniform textureBuffer sceneNormalTexels;         // R32_SFLOAT, 3 a vertex
layout(set = 0, binding = SCENE_BINDING_UVS) uniform textureBuffer sceneUvTexels;                 // R32G32_SFLOAT
layout(set = 0, binding = SCENE_BINDING_INDICES) uniform utextureBuffer sceneIndexTexels;         // R32_UINT
layout(set = 0, binding = SCENE_BINDING_GEOMETRIES) uniform utextureBuffer sceneGeometryRows;     // RGBA32UI rows
layout(set = 0, binding = SCENE_BINDING_INSTANCES) uniform utextureBuffer sceneInstanceRows;
layout(set = 0, binding = SCENE_BINDING_MATERIALS) uniform utextureBuffer sceneMaterialRows;
layout(set = 0, binding = SCENE_BINDING_EMISSIVE_TRIANGLES) uniform utextureBuffer sceneEmissiveRows;
layout(set = 0, binding = SCENE_BINDING_PUNCTUAL_LIGHTS) uniform utextureBuffer scenePunctualRows;
layout(set = 0, binding = SCENE_BINDING_CONSTANTS) uniform utextureBuffer sceneConstantRows;
layout(set = 0, binding = SCENE_BINDING_TEXTURES) uniform sampler2D sceneTextures[];

// The scene's constants are a texel buffer too, not a uniform block: lavapipe
// compiles a variant of a program for the values of the uniforms its
// branches and loops test (the light counts here), which would give every
// scene programs of its own, each compiled anew at its first dispatch.
GpuSceneConstants sceneConstants() {
  uvec4 a = GI_FETCH(sceneConstantRows, 0), b = GI_FETCH(sceneConstantRows, 1), c = GI_FETCH(sceneConstantRows, 2);
  uvec4 d = GI_FETCH(sceneConstantRows, 3), e = GI_FETCH(sceneConstantRows, 4), f = GI_FETCH(sceneConstantRows, 5);
  return GpuSceneConstants(a.x, a.y, uintBitsToFloat(a.z), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz),
                           b.w, uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz),
                           d.w, e.xy, uintBitsToFloat(e.z), e.w, f.x, uintBitsToFloat(f.y), f.z, f.w);
}

// The arrays' elements. Unused fields cost nothing: the compiler drops their fetches.
vec3 scenePosition(uint vertex) {
  int i = int(3u * vertex);
  return vec3(GI_FETCH(scenePositionTexels, i).r, GI_FETCH(scenePositionTexels, i + 1).r,
              GI_FETCH(scenePositionTexels, i + 2).r);
}
// Last frame's position of a vertex (differs from scenePosition only for deforming meshes).
vec3 scenePreviousPosition(uint vertex) {
  int i = int(3u * vertex);
  return vec3(GI_FETCH(scenePreviousPositionTexels, i).r, GI_FETCH(scenePreviousPositionTexels, i + 1).r,
              GI_FETCH(scenePreviousPositionTexels, i + 2).r);
}
vec3 sceneNormal(uint vertex) {
  int i = int(3u * vertex);
  return vec3(GI_FETCH(sceneNormalTexels, i).r, GI_FETCH(sceneNormalTexels, i + 1).r,
              GI_FETCH(sceneNormalTexels, i + 2).r);
}
vec2 sceneUvAt(uint vertex) { return GI_FETCH(sceneUvTexels, int(vertex)).rg; }
uint sceneIndex(uint i) { return GI_FETCH(sceneIndexTexels, int(i)).r; }

GpuGeometry sceneGeometry(uint index) {
  uvec4 r = GI_FETCH(sceneGeometryRows, int(index));
  return GpuGeometry(r.x, r.y, r.z, r.w);
}
// The rows of a mat4 (column-major, a column per row of the buffer) starting at `row`.
mat4 sceneRowsMat4(utextureBuffer rows, int row) {
  return mat4(uintBitsToFloat(GI_FETCH(rows, row)), uintBitsToFloat(GI_FETCH(rows, row + 1)),
              uintBitsToFloat(GI_FETCH(rows, row + 2)), uintBitsToFloat(GI_FETCH(rows, row + 3)));
}
GpuInstance sceneInstance(uint index) {
  int row = int(index) * 13;  // 208 bytes
  uvec4 ids = GI_FETCH(sceneInstanceRows, row + 12);
  return GpuInstance(sceneRowsMat4(sceneInstanceRows, row), sceneRowsMat4(sceneInstanceRows, row + 4),
                     sceneRowsMat4(sceneInstanceRows, row + 8), ids.x, ids.y, ids.z, ids.w);
}
GpuMaterial sceneMaterialData(uint index) {
  int row = int(index) * 4;  // 64 bytes
  vec4 a = uintBitsToFloat(GI_FETCH(sceneMaterialRows, row));
  vec4 b = uintBitsToFloat(GI_FETCH(sceneMaterialRows, row + 1));
  uvec4 c = GI_FETCH(sceneMaterialRows, row + 2);
  uvec4 d = GI_FETCH(sceneMaterialRows, row + 3);
  return GpuMaterial(a, b.xyz, b.w, uintBitsToFloat(c.x), uintBitsToFloat(c.y), c.z, c.w, d.x, d.y, d.z, d.w);
}
GpuEmissiveTriangle sceneEmissiveTriangle(uint index) {
  uvec4 r = GI_FETCH(sceneEmissiveRows, int(index));
  return GpuEmissiveTriangle(r.x, r.y, r.z, uintBitsToFloat(r.w));
}
GpuPunctualLight scenePunctualLight(uint index) {
  int row = int(index) * 4;  // 64 bytes
  uvec4 a = GI_FETCH(scenePunctualRows, row), b = GI_FETCH(scenePunctualRows, row + 1);
  uvec4 c = GI_FETCH(scenePunctualRows, row + 2), d = GI_FETCH(scenePunctualRows, row + 3);
  return GpuPunctualLight(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                          uintBitsToFloat(c.xyz), uintBitsToFloat(c.w), uintBitsToFloat(d.x), uintBitsToFloat(d.y),
                          uintBitsToFloat(d.z), uintBitsToFloat(d.w));
}
// The chance of picking a punctual light up to `index` (LIGHT_SAMPLER_POWER), one texel read.
float scenePunctualLightCdf(uint index) { return uintBitsToFloat(GI_FETCH(scenePunctualRows, int(index) * 4 + 3).y); }

// A GpuLightNode from its three rows.
GpuLightNode sceneNodeFromRows(uvec4 a, uvec4 b, uvec4 c) {
  return GpuLightNode(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                      uintBitsToFloat(c.x), c.y, uintBitsToFloat(c.z), c.w);
}

// LIGHT_SAMPLER_TREE's node i (GpuLightNode), after the light table.
GpuLightNode sceneLightNode(uint index) {
  const int row = int(sceneConstants().punctualLightCount) * 4 + int(index) * 3;
  return sceneNodeFromRows(GI_FETCH(scenePunctualRows, row), GI_FETCH(scenePunctualRows, row + 1),
                           GI_FETCH(scenePunctualRows, row + 2));
}

// The emissive triangles' tree's node i (GpuLightNode), after the triangles in their buffer.
GpuLightNode sceneEmissiveNode(uint index) {
  const int row = int(sceneConstants().emissiveTriangleCount) + int(index) * 3;
  return sceneNodeFromRows(GI_FETCH(sceneEmissiveRows, row), GI_FETCH(sceneEmissiveRows, row + 1),
                           GI_FETCH(sceneEmissiveRows, row + 2));
}

// The leaf node of emissive triangle k (after the tree's 2n − 1 nodes).
uint sceneEmissiveLeaf(uint k) {
  const uint n = sceneConstants().emissiveTriangleCount;
  const uint word = n * 4u + (2u * n - 1u) * 12u + k;
  return GI_FETCH(sceneEmissiveRows, int(word / 4u))[word % 4u];
}

// LIGHT_SAMPLER_TREE's cut entry k: a node whose subtree one light is taken from (after the 2n − 1 nodes).
uint sceneLightCutNode(uint k) {
  const GpuSceneConstants c = sceneConstants();
  const uint nodes = 2u * (c.punctualLightCount - c.directionalLightCount) - 1u;
  const uint word = c.punctualLightCount * 16u + nodes * 12u + k;
  return GI_FETCH(scenePunctualRows, int(word / 4u))[word % 4u];
}

// Absolute vertex indices of one triangle.
uvec3 sceneTriangle(uint geometry, uint triangle) {
  GpuGeometry g = sceneGeometry(geometry);
  uint base = g.firstIndex + 3u * triangle;
  return uvec3(sceneIndex(base), sceneIndex(base + 1u), sceneIndex(base + 2u)) + g.vertexOffset;
}

vec3 giBarycentricWeights(vec2 bary) { return vec3(1.0 - bary.x - bary.y, bary.x, bary.y); }

vec2 sceneUv(uvec3 tri, vec3 w) { return sceneUvAt(tri.x) * w.x + sceneUvAt(tri.y) * w.y + sceneUvAt(tri.z) * w.z; }

// Texture reads: fragment stages use implicit derivatives (mips), ray-traced
// stages read the top level, since a ray hit has no screen footprint.
// GI_TEXTURE: the element of the texture array, its index checked against the written count where
// ModuleDesc::checkBounds asks (an index past them reads an unwritten descriptor).
#define GI_TEXTURE(index) sceneTextures[nonuniformEXT(giCheckedTexel(int(index), int(sceneConstants().textureCount)))]
vec4 sceneTexture(uint index, vec2 uv) {
#ifdef SCENE_IMPLICIT_LOD
  return texture(GI_TEXTURE(index), uv);
#else
  return textureLod(GI_TEXTURE(index), uv, 0.0);
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
  GpuMaterial m = sceneMaterialData(materialIndex);
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
