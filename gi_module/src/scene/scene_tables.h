// The scene on the CPU as set 0 holds it: the engine's meshes packed into
// one geometry pool, materials, the emission CDF, punctual lights and the
// constants. No Vulkan: built from gi::SceneContents and checked on the way.
#pragma once
#include <glm/glm.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "gi/scene.h"
#include "scene/bvh_builder.h"
#include "shared/gpu_scene.h"

namespace gi {

struct PackedScene {
  std::vector<glm::vec3> positions, normals;  // object space
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;             // relative to their geometry's vertexOffset, Morton-sorted per geometry
  std::vector<gpu::GpuGeometry> geometries;  // every mesh's primitives, mesh by mesh
  std::vector<uint32_t> geometryVertexCount;
  std::vector<uint32_t>
      geometryFirstVertex;              // the primitive's firstVertex in its mesh's arrays (updates copy from there)
  std::vector<uint8_t> meshDeformable;  // per mesh: MeshDesc::deformable
  std::vector<uint32_t> meshFirstGeometry, meshGeometryCount;
  std::vector<glm::vec3> meshCentres;  // centre of each mesh's object-space bounds
  std::vector<gpu::GpuMaterial> materials;
  std::vector<glm::vec3> materialEmission;                // per material, W/(sr·m²)
  bool hasAlphaMask = false, hasGlossyMaterials = false;  // among materials some primitive uses
  float skyMeanLuminance = 0.0f;                          // of the map's texels (1 for a constant sky)
};

// Checks and packs the geometry and materials. The error names the field.
std::string packScene(const SceneContents& contents, PackedScene& out);
std::string checkInstances(const PackedScene& packed, std::span<const InstanceDesc> instances, const char* what);
std::string checkLights(std::span<const LightDesc> lights, const char* what);

glm::mat4 toMat4(const float (&m)[16]);
// Element i of a strided CPU array (stride 0: packed, `packedSize` bytes apart).
const float* element(const float* base, uint32_t stride, uint32_t packedSize, uint32_t i);

// The emissive triangles as the shaders read them: one entry per triangle of every emissive primitive of
// every instance, in (instance, geometry, triangle) order (lights.glsl's giFindEmissive searches it), each
// with its chance under LIGHT_SAMPLER_POWER (world area × luminance(emission); a triangle without area has
// none) as a cdf, and the tree LIGHT_SAMPLER_TREE walks over them (2n − 1 nodes, cosine emitters). Empty
// triangles and nodes when no triangle has power. totalPower: Σ of the weights.
struct EmissiveTable {
  std::vector<gpu::GpuEmissiveTriangle> triangles;
  std::vector<gpu::GpuLightNode> nodes;
  float totalPower = 0.0f;
  // The triangles the shaders pick from (GpuSceneConstants::emissiveTriangleCount).
  uint32_t pickable() const { return nodes.empty() ? 0u : uint32_t(triangles.size()); }
};
EmissiveTable emissiveTable(const PackedScene& packed, std::span<const InstanceDesc> instances);
// Whether some primitive of `mesh` emits light (its instances and vertices are in the emissive table).
bool meshEmits(const PackedScene& packed, uint32_t mesh);
// The scene's emission buffer (16-byte texels): the n triangles, their tree's nodes (3 texels each), then
// each triangle's leaf node (a word each).
std::vector<uint32_t> emissiveTableWords(const EmissiveTable& table);
inline size_t emissiveTableCapacityWords(size_t triangles) {
  const size_t words =
      (triangles * sizeof(gpu::GpuEmissiveTriangle) + (triangles ? 2 * triangles - 1 : 0) * sizeof(gpu::GpuLightNode)) /
          4 +
      triangles;
  return std::max<size_t>((words + 3) / 4 * 4, 4);  // whole texels, at least one (a buffer is never empty)
}
// The punctual lights as the shaders read them: the directional ones first, each light's chance of being
// picked by LIGHT_SAMPLER_POWER (its power; directional lights' over the scene's disc of diameter
// sceneExtent), the tree LIGHT_SAMPLER_TREE walks over the others (2n − 1 nodes for n lights) and its cut
// of min(cutSize, n) subtrees (split by power from the root), one light a vertex from each.
struct LightTable {
  std::vector<gpu::GpuPunctualLight> lights;
  std::vector<gpu::GpuLightNode> nodes;
  std::vector<uint32_t> cut;
  uint32_t directionalCount = 0;
};
LightTable lightTable(std::span<const LightDesc> lights, float sceneExtent, uint32_t cutSize);
// Whether NEE picks among punctual lights (gi::picksPunctualLights): power with more than one,
// the tree with more point and spot lights than its cut has subtrees (each subtree one light is exact).
bool picksPunctualLights(const gpu::GpuSceneConstants& c);
// The light facts of gi::SceneDesc from the scene's constants: its sampler, and whether NEE picks under each.
void setLightFacts(const gpu::GpuSceneConstants& c, SceneDesc& facts);
// The lights, then the nodes: the scene's punctual-light buffer.
std::vector<uint32_t> lightTableWords(const LightTable& table);
// The words that buffer needs for `lights` lights of any types (their tree and cut are largest when none
// is directional), in whole 16-byte texels: the shaders read the cut's words four at a time.
inline size_t lightTableCapacityWords(size_t lights) {
  const size_t words =
      (lights * sizeof(gpu::GpuPunctualLight) + (lights ? 2 * lights - 1 : 0) * sizeof(gpu::GpuLightNode)) / 4 + lights;
  return (words + 3) / 4 * 4;
}
std::vector<gpu::GpuInstance> gpuInstances(const PackedScene& packed, std::span<const InstanceDesc> instances,
                                           std::span<const glm::mat4> previous);
std::vector<BvhMesh> bvhMeshes(const PackedScene& packed);
std::vector<BvhInstance> bvhInstances(std::span<const InstanceDesc> instances, std::span<const uint8_t> forceMovable);

// World bounds of the instanced geometry (empty: min > max).
void worldBounds(const PackedScene& packed, std::span<const InstanceDesc> instances, glm::vec3& lo, glm::vec3& hi);

// A rough scale of the radiance the scene will hold (SceneDesc::typicalRadiance).
float typicalRadiance(const PackedScene& packed, std::span<const LightDesc> lights, const SkyDesc& sky, float extent);

}  // namespace gi
