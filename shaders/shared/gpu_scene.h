// The scene as the GPU sees it: one descriptor set (set 0) shared by the
// reference path tracer, the G-buffer pass and the GI module.
// Units: metres, radiance in W/(sr·m²), punctual intensity in W/sr
// (point/spot) or irradiance in W/m² (directional), all linear RGB.
#ifndef GI_GPU_SCENE_H
#define GI_GPU_SCENE_H
#include "gpu_common.h"
#include "scene_modes.h"
#include "light_tree.h"

GPU_NAMESPACE_BEGIN

// Set 0 bindings.
GPU_CONST SCENE_BINDING_TLAS = 0;              // accelerationStructureEXT
// Bindings 1–10 and 15 are uniform texel buffers (scene.glsl reads them): on
// lavapipe a texel fetch is one call for all lanes where a storage-buffer
// load with a per-lane address unrolls lane by lane, to run and to compile.
GPU_CONST SCENE_BINDING_POSITIONS = 1;         // R32_SFLOAT: xyz per vertex, object space
GPU_CONST SCENE_BINDING_NORMALS = 2;           // R32_SFLOAT: xyz per vertex, object space, unit length
GPU_CONST SCENE_BINDING_UVS = 3;               // R32G32_SFLOAT: uv per vertex
GPU_CONST SCENE_BINDING_INDICES = 4;           // R32_UINT, relative to GpuGeometry.vertexOffset
GPU_CONST SCENE_BINDING_GEOMETRIES = 5;        // GpuGeometry[] as RGBA32UI rows (16 bytes each)
GPU_CONST SCENE_BINDING_INSTANCES = 6;         // GpuInstance[], RGBA32UI rows
GPU_CONST SCENE_BINDING_MATERIALS = 7;         // GpuMaterial[], RGBA32UI rows
GPU_CONST SCENE_BINDING_EMISSIVE_TRIANGLES = 8;// GpuEmissiveTriangle[], RGBA32UI rows (placeholder when none)
GPU_CONST SCENE_BINDING_PUNCTUAL_LIGHTS = 9;   // GpuPunctualLight[], RGBA32UI rows (placeholder when none)
GPU_CONST SCENE_BINDING_CONSTANTS = 10;        // GpuSceneConstants, RGBA32UI rows (a texel buffer: see scene.glsl)
// The compute traversal backend's two-level BVH (shared/gpu_bvh.h). Present
// whatever the backend; binding 0 (the TLAS) only where the device has ray queries.
// Each is an RGBA32UI uniform texel buffer holding the structs' 16-byte rows.
GPU_CONST SCENE_BINDING_BVH_NODES = 11;        // GpuBvhNode[], every bottom level
GPU_CONST SCENE_BINDING_BVH_TRIANGLES = 12;    // GpuBvhTriangle[]
GPU_CONST SCENE_BINDING_BVH_TOP_NODES = 13;    // GpuBvhNode[], the top level (node 0 = root), rewritten by updates
GPU_CONST SCENE_BINDING_BVH_INSTANCES = 14;    // GpuBvhInstance[], rewritten by updates
GPU_CONST SCENE_BINDING_SKY_DISTRIBUTION = 15;// R32_SFLOAT: the sky map's sampling tables (sky.glsl); a placeholder without a map
// R32_SFLOAT: the positions of the previous frame, for the motion vectors of deforming meshes
// (gi::updateMeshVertices copies a mesh's positions here before writing the new ones); without
// deformable meshes the positions' own view.
GPU_CONST SCENE_BINDING_PREVIOUS_POSITIONS = 16;
GPU_CONST SCENE_BINDING_TEXTURES = 17;         // sampler2D[], variable count (must stay the last binding)
GPU_CONST SCENE_BINDING_COUNT = 18;

GPU_CONST MATERIAL_FLAG_GLOSSY = 1u;       // has a GGX lobe (materialHasGlossyLobe, or a roughness texture)
GPU_CONST MATERIAL_FLAG_ALPHA_MASK = 2u;   // alphaMode MASK: texels below alphaCutoff are holes
GPU_CONST MATERIAL_FLAG_EMISSIVE = 4u;     // emissive (factor × strength) is non-zero
GPU_CONST NO_TEXTURE = 0xffffffffu;

// The glossy-material rule, once for the scene's materials (scene_tables.cpp) and the G-buffer's pixels
// (GlossyFlag::FromMaterial, gi_frame.glsl): a GGX lobe only where it changes the result noticeably:
// metallic, or smoother than a perceptual roughness of 0.9.
GPU_FN bool materialHasGlossyLobe(float metallic, float roughness) { return metallic > 0.0f || roughness < 0.9f; }

struct GpuMaterial {
  vec4 baseColor;        // linear RGBA factor, multiplied by the sRGB-decoded texture
  vec3 emission;         // emissiveFactor × emissive_strength, W/(sr·m²) per unit texel
  float metallic;        // [0,1]
  float roughness;       // [0,1] perceptual; GGX alpha = roughness²
  float alphaCutoff;     // [0,1], used with MATERIAL_FLAG_ALPHA_MASK
  uint baseColorTexture; // index into the texture array or NO_TEXTURE
  uint metallicRoughnessTexture; // G = roughness, B = metallic (glTF)
  uint emissiveTexture;
  uint flags;            // MATERIAL_FLAG_*
  uint pad0;
  uint pad1;
};
GPU_ASSERT_SIZE(GpuMaterial, 64);

// One glTF primitive: a BLAS geometry. A TLAS instance's custom index is the
// index of its mesh's first geometry; the ray query's geometry index adds to it.
struct GpuGeometry {
  uint firstIndex;   // into SCENE_BINDING_INDICES
  uint vertexOffset; // added to every index
  uint material;
  uint triangleCount;
};
GPU_ASSERT_SIZE(GpuGeometry, 16);

struct GpuInstance {
  mat4 worldFromObject;
  mat4 normalWorldFromObject;   // inverse-transpose of the upper 3×3, w unused
  mat4 previousWorldFromObject; // last frame's transform, for motion vectors
  uint firstGeometry;
  uint geometryCount;
  uint pad0;
  uint pad1;
};
GPU_ASSERT_SIZE(GpuInstance, 208);

// An emissive triangle, picked for next-event estimation with probability
// proportional to its power (world area × luminance(emission)); the cumulative
// distribution sits in `cdf`, normalised so the last entry is 1.
struct GpuEmissiveTriangle {
  uint instance;
  uint geometry;   // absolute geometry index
  uint triangle;   // within the geometry
  float cdf;
};
GPU_ASSERT_SIZE(GpuEmissiveTriangle, 16);

GPU_CONST PUNCTUAL_POINT = 0u;
GPU_CONST PUNCTUAL_SPOT = 1u;
GPU_CONST PUNCTUAL_DIRECTIONAL = 2u;

struct GpuPunctualLight {
  vec3 position;   // world, metres (unused for directional)
  uint type;       // PUNCTUAL_*
  vec3 direction;  // world, unit: the direction the light travels
  float range;     // metres; 0 = infinite
  vec3 intensity;  // colour × intensity: W/sr, or W/m² for directional
  float cosInner;  // spot: cos(innerConeAngle)
  float cosOuter;  // spot: cos(outerConeAngle)
  float cdf;       // LIGHT_SAMPLER_POWER: the chance of picking a light up to this one (the last: 1); of the
                   // directional ones (first in the table) under LIGHT_SAMPLER_TREE
  float pad1;
  float pad2;
};
GPU_ASSERT_SIZE(GpuPunctualLight, 64);

struct GpuSceneConstants {
  uint emissiveTriangleCount;
  uint punctualLightCount;
  float pad0;
  float sceneExtent;           // largest dimension of the scene bounds, metres
  vec3 boundsMin;
  uint directionalLightCount;  // the light table's first ones (secondary rays offset by ULPs, giOffsetRay: no
                               // scene-scaled epsilon here)
  vec3 boundsMax;
  uint lightCutSize;           // LIGHT_SAMPLER_TREE: the subtrees a vertex takes one light from (the cut after the
                               // tree in the light buffer; min(SceneCreateDesc::lightTreeCut, point and spot lights))
  // The sky: radiance of rays that leave the scene. Equirectangular map
  // (skyTexture; +Y up, u = 0.5 + atan(x, −z)/2π, v = acos(y)/π, texels read
  // nearest) times skyRadiance, or skyRadiance alone (NO_TEXTURE). Black sky:
  // skyRadiance 0 and SCENE_SPEC_HAS_SKY off.
  vec3 skyRadiance;      // W/(sr·m²), or the map's scale
  uint skyTexture;       // index into SCENE_BINDING_TEXTURES, or NO_TEXTURE
  uvec2 skySize;         // map texels (the sampling tables' resolution); 0 without a map
  float skyDistributionSum; // Σ luminance × sin θ over the map's texels (before normalising)
  uint lightSampler;     // LIGHT_SAMPLER_*
  uint textureCount;     // SCENE_BINDING_TEXTURES's written elements (the sky's map included): what a material's
                         // or the sky's texture index is checked against (ModuleDesc::checkBounds)
  float skyIrradiance;   // W/m²: a quarter of the sky's luminance integrated over the sphere (π × luminance for
                         // a constant sky): LIGHT_SAMPLER_TREE's importance of the sky beside the emissive
                         // triangles' tree (giSkySelection); 0: no sky
  uint pad1, pad2;
};
GPU_ASSERT_SIZE(GpuSceneConstants, 96);

// Camera shared by every pass. View space is right-handed, looking down -Z.
struct GpuCamera {
  mat4 worldFromView;
  mat4 viewFromWorld;
  mat4 clipFromWorld;          // Vulkan clip space (y down, depth 0..1)
  mat4 previousClipFromWorld;
  vec3 position;
  float tanHalfFovY;
  vec2 imageSize;              // pixels
  float aspect;                // width / height
  float pad0;
  vec2 ndcShift;               // the projection's shift in NDC (clipFromView[2].xy = −ndcShift): sub-pixel
                               // jitter (TAA) and off-axis projections; primary rays follow it
  vec2 pad1;
};
GPU_ASSERT_SIZE(GpuCamera, 304);

// The primary ray through `pixel` (continuous: (x + 0.5, y + 0.5) is the
// centre of pixel (x, y), y down), matching the raster projection exactly;
// shared by the shaders (camera.glsl) and CPU tracing (engine/cpu_tracer).
GPU_FN vec3 giCameraRayDirection(GpuCamera cam, vec2 pixel) {
  vec2 ndc = pixel / cam.imageSize * 2.0f - 1.0f - cam.ndcShift;
  vec3 view = vec3(ndc.x * cam.tanHalfFovY * cam.aspect, -ndc.y * cam.tanHalfFovY, -1.0f);
  return normalize(mat3(cam.worldFromView) * view);
}

GPU_NAMESPACE_END
#endif
