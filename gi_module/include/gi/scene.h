// gi/scene.h — the scene as the module traces it, described by the engine in
// its own terms and built by the module: meshes as CPU arrays or the
// engine's device buffers, glTF
// metallic-roughness materials with the engine's image views, punctual
// lights, instances and the sky. The module packs the geometry, builds the
// emission CDF, the compute traversal's BVH and (for ray queries) the
// BLAS/TLAS, and fills descriptor set 0 (shaders/shared/gpu_scene.h). The
// engine hands sceneDesc(scene) to gi::create or gi::setScene; its own
// passes may bind the same set 0 (the sample engine's G-buffer and reference
// path tracer do).
//
// Like the rest of the module, a Scene records into the engine's command
// buffers and never submits or waits.
#pragma once
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <iterator>
#include <span>

#include "gi/gi.h"

namespace gi {

struct Scene;

// One glTF primitive: a range of a mesh's indices with one material.
struct PrimitiveDesc {
  uint32_t firstIndex = 0;   // into MeshDesc::indices
  uint32_t indexCount = 0;   // a multiple of 3 (triangle lists)
  uint32_t firstVertex = 0;  // the primitive's indices count from this vertex of the mesh's arrays
  uint32_t vertexCount = 0;  // and stay below this many
  uint32_t material = 0;     // into SceneContents::materials
};

// A vertex stream in one of the engine's device buffers, read through its
// device address by a compute pass: the buffer was created with
// SHADER_DEVICE_ADDRESS usage (and its memory with DEVICE_ADDRESS), the
// device with bufferDeviceAddress. Address and stride are multiples of 4 bytes.
struct DeviceStream {
  VkDeviceAddress address = 0;  // of vertex 0 (0: absent, for uvs only)
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t stride = 0;  // bytes between vertices; 0 = the format's size
};

// Formats accepted for each stream (xyz of a 4-component normal or position
// is used; normals are normalised after decoding):
//   positions  R32G32B32_SFLOAT, R32G32B32A32_SFLOAT, R16G16B16A16_SFLOAT
//   normals    R32G32B32_SFLOAT, R32G32B32A32_SFLOAT, R16G16B16A16_SFLOAT,
//              R16G16B16A16_SNORM, R8G8B8A8_SNORM
//   uvs        R32G32_SFLOAT, R16G16_SFLOAT, R16G16_UNORM
//   indices    VK_INDEX_TYPE_UINT32, VK_INDEX_TYPE_UINT16
// Every stream is read in aligned 32-bit words: 16-bit indices in pairs, so
// with an odd index count the word holding the last index is read whole, and
// the buffer must extend to its end (its size rounded up to 4 bytes, as
// Vulkan's allocations are anyway); reading 16-bit words alone would need the
// device's storageBuffer16BitAccess, which the module does not ask for.
struct DeviceMeshDesc {
  DeviceStream positions, normals, uvs;
  VkDeviceAddress indices = 0;  // of index 0
  VkIndexType indexType = VK_INDEX_TYPE_UINT32;
};

// A mesh as CPU arrays (the module copies what it needs during createScene),
// or in the engine's device buffers (`device.positions.address` set, the
// CPU pointers null). The compute traversal's BVH and the emission CDF are
// built on the CPU, so device meshes are read back: createScene records a
// pass that decodes them into a host-visible buffer, and finishSceneUpload
// (once that completed) builds the scene from them into a second command
// buffer. The engine's buffers may be freed once createScene's commands completed.
struct MeshDesc {
  const float* positions = nullptr;  // xyz per vertex, object space, metres
  uint32_t positionStride = 0;       // bytes between vertices; 0 = 12 (packed)
  const float* normals = nullptr;    // xyz, unit length (required: generate them for files without)
  uint32_t normalStride = 0;         // 0 = 12
  const float* uvs = nullptr;        // uv per vertex; null: no texture coordinates (0, 0)
  uint32_t uvStride = 0;             // 0 = 8
  uint32_t vertexCount = 0;
  const uint32_t* indices = nullptr;
  uint32_t indexCount = 0;
  std::span<const PrimitiveDesc> primitives;
  DeviceMeshDesc device;  // instead of the arrays above (vertexCount, indexCount, primitives apply)
  // Its vertices change through updateMeshVertices (a skinned or morphing mesh): its instances stay out of
  // the BVH's merged static level, and with ray queries its BLAS is built to be updated.
  bool deformable = false;
};

enum class AlphaMode : uint32_t { Opaque = 0, Mask, Blend };  // Blend is lit as opaque

// glTF 2.0 metallic-roughness, with KHR_materials_emissive_strength.
struct MaterialDesc {
  float baseColor[4] = {1.0f, 1.0f, 1.0f, 1.0f};  // linear factor × the texture
  float metallic = 0.0f;                          // [0,1]: a dielectric unless set (glTF's factor defaults to 1:
                                                  // a loader sets what the file says)
  float roughness = 1.0f;                         // [0,1], perceptual (GGX α = roughness²), glTF's default
  float emissive[3] = {0.0f, 0.0f, 0.0f};         // emissiveFactor, [0,1]
  float emissiveStrength = 1.0f;                  // emission = emissive × this, W/(sr·m²)
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;               // Mask: base colour alpha below it is a hole
  int32_t baseColorTexture = -1;          // into SceneContents::textures, or −1
  int32_t metallicRoughnessTexture = -1;  // g = roughness, b = metallic
  int32_t emissiveTexture = -1;
};

// The engine's texture: its view and sampler, sampled in
// SHADER_READ_ONLY_OPTIMAL by every stage that binds set 0. Base colour and
// emissive views should be _SRGB formats (decoded on read). The engine keeps
// them alive while the scene exists.
struct TextureDesc {
  VkImageView view = VK_NULL_HANDLE;
  VkSampler sampler = VK_NULL_HANDLE;
};

enum class LightType : uint32_t { Point = 0, Spot = 1, Directional = 2 };  // KHR_lights_punctual

struct LightDesc {
  LightType type = LightType::Point;
  float position[3] = {0.0f, 0.0f, 0.0f};    // world, metres (point, spot)
  float direction[3] = {0.0f, 0.0f, -1.0f};  // world, unit: the way the light travels (spot, directional)
  float intensity[3] = {1.0f, 1.0f, 1.0f};   // colour × intensity: W/sr (point, spot), W/m² (directional)
  float range = 0.0f;                        // metres; 0 = unlimited
  float innerConeAngle = 0.0f;               // radians (spot)
  float outerConeAngle = 0.7853982f;
};

struct InstanceDesc {
  uint32_t mesh = 0;                                                             // into SceneContents::meshes
  float worldFromObject[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // column-major, affine
  bool movable = false;  // may move through updateInstances (kept out of the static BVH level)
};

// Radiance of rays that leave the scene: a constant, or an equirectangular
// map (+Y up, −Z at the centre column, row 0 at the top) scaled by it.
// Black (radiance 0) is no sky: no pass compiles the sky in.
struct SkyDesc {
  float radiance[3] = {0.0f, 0.0f, 0.0f};  // W/(sr·m²), or the map's scale
  const float* map = nullptr;              // linear rgb(a) texels, row-major; null: constant sky
  uint32_t width = 0, height = 0;
  uint32_t channels = 3;  // 3 or 4 (alpha ignored)
};

struct SceneContents {
  std::span<const MeshDesc> meshes;
  std::span<const MaterialDesc> materials;
  std::span<const TextureDesc> textures;
  std::span<const LightDesc> lights;
  std::span<const InstanceDesc> instances;
  SkyDesc sky;
};

// gpu::LIGHT_SAMPLER_*'s names (command lines, file names, overlays), indexed by the constant.
inline constexpr const char* kLightSamplerNames[] = {"all", "power", "tree"};
static_assert(std::size(kLightSamplerNames) == gpu::LIGHT_SAMPLER_TREE + 1, "a name for every light sampler");

struct SceneCreateDesc {
  uint32_t structSize = sizeof(SceneCreateDesc);  // leave as is
  PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;  // with gi/device.h's features for this traversal
  // Traversal::Compute: the module's BVH (built on the CPU with Embree),
  // walked in its shaders (any device). Traversal::RayQuery: BLAS/TLAS (the
  // device has VK_KHR_acceleration_structure and VK_KHR_ray_query enabled),
  // and no CPU BVH unless bothTraversals.
  Traversal traversal = Traversal::Compute;
  // With Traversal::RayQuery: also the compute traversal's BVH, so that either
  // backend may trace the scene (SceneDesc::traversal switched; tools and tests
  // that compare the two). Costs the CPU build and its memory.
  bool bothTraversals = false;
  // Next-event estimation over the punctual lights, for the module and the engine's reference alike.
  // gpu::LIGHT_SAMPLER_ALL: a shadow ray to every light at every path vertex (exact; cost grows with
  // the count). gpu::LIGHT_SAMPLER_POWER: one light a vertex, picked by its power (the same
  // expectation; cost independent of the count, noise growing with it). gpu::LIGHT_SAMPLER_TREE:
  // every directional light, and for the point and spot lights lightTreeCut shadow rays a vertex, one
  // light from each subtree of a cut of a tree over them, picked down it by power over distance² and
  // the angle to the surface (the same expectation; cost independent of the count; exact, as all,
  // with no more lights than lightTreeCut: the default, which leaves scenes of a few lights as they
  // were and keeps a frame's cost flat however many lights a scene has). The tree is rebuilt by
  // gi::updateLights. The emissive triangles take one shadow ray a vertex under every sampler: picked by
  // power (world area × luminance of the emission) under all and power, down a tree of their own under
  // tree (bounds, power and the cone of directions each emits in; rebuilt when updateInstances or
  // updateMeshVertices moves them; with more than two triangles: one quad lamp's are picked by power),
  // with MIS against BSDF sampling either way.
  uint32_t lightSampler = gpu::LIGHT_SAMPLER_TREE;  // kLightSamplerNames names them
  uint32_t lightTreeCut = 4;  // [1, 64]: LIGHT_SAMPLER_TREE's subtrees (shadow rays a vertex for its lights)
  // A deformable mesh is rebuilt rather than refit once its refit compute-BVH level's surface-area cost
  // (SceneInfo::refitCostRatio) exceeds this many times its cost when last built: its level by Embree on
  // the CPU (as at createScene) and, with ray queries, its BLAS built anew. 0: always refit. Measured after
  // each update with CPU arrays; with device streams on positions read back now and then (one mesh at a
  // time: an update copies them to host-visible memory behind an event, a later update of the mesh that
  // finds it set measures them; no wait, so the measure lags the pose by the frames in flight). A scene
  // for ray queries alone keeps its deformable meshes' levels on the CPU for this measure (never uploaded;
  // host memory only). The default is below the first pose where refit levels traced slower
  // (docs/RESULTS.md, "Refit against rebuild"). A rebuild is Embree's build on the CPU (about 25 ms for
  // 10,000 triangles there, 870 ms for a million): see rebuildOffThread.
  float rebuildCostRatio = 1.5f;
  // true: a rebuild runs on a worker thread of the module's, one level at a time, from the pose of the
  // update that found the level degraded; the level is refit meanwhile, and the first update of the mesh
  // after the build finished installs it (its nodes written into that update's command buffer, refit to
  // that pose; the BLAS is built anew at once on the device). The worker also walks the new level's cost
  // in the pose it was built from and derives its refit order, so the update calls then cost no more than
  // a refit, except the install's copies of the level into the BVH and its writes. false: the
  // update that finds the level degraded rebuilds it itself, the same frames in every run.
  bool rebuildOffThread = true;
  const VkAllocationCallbacks* allocationCallbacks = nullptr;
  uint64_t memoryBudgetBytes = 0;  // 0 = no limit
  DeviceMemoryCallbacks
      deviceMemory;  // set: every buffer and image takes its memory from the engine (gi/device_memory.h)
};

// Validates `contents` (indices within their vertex ranges, material,
// texture and mesh references, finite values), packs it, and records into
// `cmd` the uploads and acceleration-structure builds, ending with a barrier
// that makes set 0 visible to vertex, fragment and compute shaders. The scene
// is usable by commands recorded after these in `cmd` or submitted later.
// The engine's arrays may be freed once this returns. Errors name the field:
// "contents.meshes[2].primitives[0]: index 812 is not below vertexCount 800".
// With device meshes only their read-back is recorded (and only their
// descriptions are checked): the scene is built by finishSceneUpload.
Error createScene(const SceneCreateDesc& desc, const SceneContents& contents, VkCommandBuffer cmd, Scene*& out);
// Call once the command buffer createScene recorded into has completed: frees
// its staging memory. A scene with device meshes is built here, from what was
// read back, recording its uploads and builds into `cmd` (required then; the
// scene is usable by commands after them, and this call's own staging is
// freed by the next finishSceneUpload or by destroyScene); the checks of
// createScene apply and their errors are returned here. Without device
// meshes `cmd` is not used.
Error finishSceneUpload(Scene* scene, VkCommandBuffer cmd = VK_NULL_HANDLE);
// False while a scene with device meshes waits for finishSceneUpload (its
// sceneDesc has no set yet).
bool sceneBuilt(const Scene* scene);
// The caller ensures the GPU no longer uses the scene (and gi modules were
// given another scene or destroyed first).
void destroyScene(Scene* scene);

// What gi::create and gi::setScene take: set 0 and the facts derived from
// the contents (which lights, alpha masks, glossy materials, sky; extent,
// typical radiance; traversal).
SceneDesc sceneDesc(const Scene* scene);

// New transforms for moving instances, one per instance in createScene's
// order (same meshes). Records into `cmd` the writes of the instance table,
// the emission CDF and the BVH's top level (vkCmdUpdateBuffer: the data
// travels in the command buffer) and the TLAS rebuild, with barriers after
// every earlier command's reads and before every later command: frames in
// flight keep the tables they were recorded with, and an engine updates every
// frame without waiting on any fence but the one its frame slot needs (call
// it once a frame, before the frame's G-buffer and gi::recordFrame in the same
// or an earlier submission). An instance that was not `movable` costs, on its
// first move, one rebuild of the BVH's bottom levels into new buffers and a
// rewrite of set 0: the frames that read set 0 must have completed for that one.
// Light cached by gi modules is the engine's to invalidate.
Error updateInstances(Scene* scene, VkCommandBuffer cmd, std::span<const InstanceDesc> instances);
// New punctual lights, as many as at createScene, written into `cmd` like the
// tables above (the light tree rebuilt on the CPU).
Error updateLights(Scene* scene, VkCommandBuffer cmd, std::span<const LightDesc> lights);

// A deformable mesh's new vertices, as many and in the order of its MeshDesc: CPU arrays (copied into the
// command buffer), or streams in the engine's device buffers (decoded on the device, no read-back), in
// DeviceMeshDesc's position and normal formats. The module's positions, normals and BVH follow.
struct MeshVertices {
  const float* positions = nullptr;             // xyz per vertex, object space, metres
  uint32_t positionStride = 0;                  // 0 = 12
  const float* normals = nullptr;               // xyz, unit length
  uint32_t normalStride = 0;                    // 0 = 12
  DeviceStream devicePositions, deviceNormals;  // instead of the arrays (both, or neither)
};

// New vertices for deformable mesh `mesh` (MeshDesc::deformable), recorded into `cmd` like updateInstances
// (after every earlier command's reads, before every later command): the packed positions and normals are
// written, the compute traversal's BVH is refit on the device (its triangles, its bottom level a level at a
// time, the top level; the tree keeps the shape of the pose it was built in, so traversal stays exact and
// slows as the deformation grows), and with ray queries the mesh's BLAS is updated and the TLAS rebuilt.
// With CPU arrays the level and the BLAS are rebuilt instead where refits have degraded the level past
// SceneCreateDesc::rebuildCostRatio (the level off this thread by default: SceneCreateDesc::rebuildOffThread),
// and the emission table follows the new areas. An emissive mesh posed by device streams keeps the table
// its areas and bounds gave when last built on the CPU: its picks stay unbiased (their chances over each
// triangle's area in the pose being traced) and grow noisier as it deforms away. The G-buffer's motion
// vectors of deforming surfaces are the engine's (previous positions): the module's temporal passes see
// them as moving geometry.
Error updateMeshVertices(Scene* scene, VkCommandBuffer cmd, uint32_t mesh, const MeshVertices& vertices);
// A frame in which deformable mesh `mesh` holds still (its animation paused, its character at rest): its
// previous positions become its current ones, so the G-buffer's motion vectors read no motion there;
// nothing is written, refit or rebuilt. Without it the last update's motion stays (set 0's previous
// positions are those the last update replaced). One call after the last update is enough; recorded into
// `cmd` like updateMeshVertices.
Error holdMeshVertices(Scene* scene, VkCommandBuffer cmd, uint32_t mesh);

struct SceneInfo {
  uint32_t triangles = 0;                                    // instanced
  uint32_t emissiveTriangles = 0;                            // NEE picks among these (their CDF, their tree)
  double bvhBottomBuildMs = 0.0;                             // CPU time of the BVH's bottom levels (paid at create)
  double bvhTopBuildMs = 0.0;                                // of its last top-level build
  uint64_t memoryBytes = 0;                                  // device memory the scene holds
  float boundsMin[3] = {0, 0, 0}, boundsMax[3] = {0, 0, 0};  // world, metres
  // The deformable mesh updateMeshVertices last measured (each update with CPU arrays, device streams when
  // their read-back positions arrived): its compute-BVH level's surface-area cost in that pose over its
  // cost when last built (1: as built), and the rebuilds SceneCreateDesc::rebuildCostRatio has made since
  // createScene.
  float refitCostRatio = 0.0f;
  uint32_t levelRebuilds = 0;
  bool levelRebuildRunning = false;  // a rebuild on the module's worker thread, not yet installed
};
SceneInfo sceneInfo(const Scene* scene);

}  // namespace gi
