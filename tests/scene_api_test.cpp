// The module's scene API (gi/scene.h): bad contents are named errors, and an
// instance moved through gi::updateInstances renders as a scene loaded in
// that pose.
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <cstring>

#include "engine_device_memory.h"
#include "gi/scene.h"
#include "gpu_test.h"
#include "quad_contents.h"
#include "scene/scene.h"

class SceneApiTest : public GpuTest {
 protected:
  static gi::SceneCreateDesc createDesc() {
    gi::SceneCreateDesc d;
    d.getInstanceProcAddr = vkGetInstanceProcAddr;
    d.instance = ctx.instance;
    d.physicalDevice = ctx.physicalDevice;
    d.device = ctx.device;
    d.traversal = ctx.rayQuery ? gi::Traversal::RayQuery : gi::Traversal::Compute;
    return d;
  }
  // createScene into a one-shot command buffer; the scene (or null) in `out`.
  static gi::Error create(const gi::SceneContents& contents, gi::Scene*& out) {
    gi::Error e;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::createScene(createDesc(), contents, cmd, out); });
    return e;
  }
};

using Quad = QuadContents;

TEST_F(SceneApiTest, GoodContentsBuildAndBadOnesAreNamedErrors) {
  {
    Quad q;
    gi::Scene* scene = nullptr;
    ASSERT_FALSE(create(q.contents(), scene));
    ASSERT_NE(scene, nullptr);
    const gi::SceneDesc d = gi::sceneDesc(scene);
    EXPECT_TRUE(d.hasPunctualLights);
    EXPECT_FALSE(d.hasEmissiveTriangles);
    EXPECT_FALSE(d.hasGlossyMaterials);  // a default MaterialDesc is a rough dielectric
    EXPECT_EQ(gi::sceneInfo(scene).triangles, 2u);
    EXPECT_FLOAT_EQ(d.extent, 1.0f);
    // Updates: counts and meshes must match what was created.
    std::vector<gi::InstanceDesc> two(2, q.instance);
    gi::Error e;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::updateInstances(scene, cmd, two); });
    EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange);
    EXPECT_NE(e.message.find("2 instances given, the scene has 1"), std::string::npos) << e.message;
    gi::InstanceDesc otherMesh = q.instance;
    otherMesh.mesh = 1;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::updateInstances(scene, cmd, std::span(&otherMesh, 1)); });
    EXPECT_NE(e.message.find("instances[0].mesh"), std::string::npos) << e.message;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::updateLights(scene, cmd, {}); });
    EXPECT_NE(e.message.find("0 lights given, the scene has 1"), std::string::npos) << e.message;
    gi::LightDesc bad = q.light;
    bad.intensity[1] = NAN;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::updateLights(scene, cmd, std::span(&bad, 1)); });
    EXPECT_NE(e.message.find("lights[0]: intensity"), std::string::npos) << e.message;
    gi::destroyScene(scene);
  }
  struct Case {
    const char* what;
    void (*spoil)(Quad&);
    const char* field;
  };
  const Case cases[] = {
      {"index past the primitive's vertices", [](Quad& q) { q.indices[4] = 7; },
       "contents.meshes[0].primitives[0]: index 7 is not below vertexCount 4"},
      {"index count not a multiple of 3", [](Quad& q) { q.primitive.indexCount = 5; }, "indexCount = 5"},
      {"indices past the array", [](Quad& q) { q.primitive.firstIndex = 3; }, "run past indexCount 6"},
      {"material out of range", [](Quad& q) { q.primitive.material = 3; }, "primitives[0].material = 3"},
      {"no normals", [](Quad& q) { q.mesh.normals = nullptr; }, "positions and normals are required"},
      {"texture that does not exist", [](Quad& q) { q.material.baseColorTexture = 0; },
       "materials[0].baseColorTexture = 0"},
      {"negative emission", [](Quad& q) { q.material.emissive[0] = -1.0f; }, "materials[0]: emissive"},
      {"roughness above 1", [](Quad& q) { q.material.roughness = 2.0f; }, "materials[0].roughness"},
      {"instance of a missing mesh", [](Quad& q) { q.instance.mesh = 4; }, "instances[0].mesh = 4"},
      {"non-finite transform", [](Quad& q) { q.instance.worldFromObject[13] = INFINITY; },
       "instances[0].worldFromObject"},
      {"NaN vertex", [](Quad& q) { q.positions[4] = NAN; }, "vertex position is not finite"},
      {"light with a NaN direction", [](Quad& q) { q.light.direction[0] = NAN; }, "lights[0]: position and direction"},
  };
  for (const Case& c : cases) {
    Quad q;
    gi::SceneContents contents = q.contents();
    c.spoil(q);
    gi::Scene* scene = nullptr;
    gi::Error e = create(contents, scene);
    EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange) << c.what;
    EXPECT_NE(e.message.find(c.field), std::string::npos) << c.what << ": " << e.message;
    EXPECT_EQ(scene, nullptr) << c.what;
  }
  Quad q;
  gi::SceneContents contents = q.contents();
  const float sky[3] = {1.0f, NAN, 0.0f};
  contents.sky.radiance[0] = 1.0f;
  contents.sky.map = sky;
  contents.sky.width = contents.sky.height = 1;
  gi::Scene* scene = nullptr;
  gi::Error e = create(contents, scene);
  EXPECT_NE(e.message.find("contents.sky.map texel (0, 0)"), std::string::npos) << e.message;
  EXPECT_EQ(scene, nullptr);
}

// The Cornell box's tall block moved through gi::updateInstances renders as
// the same scene loaded with the block already there: bit for bit where the
// block was created movable (the same BVH levels either way), and within
// float rounding where it was merged into the static level and had to be
// taken out of it on the first move.
TEST_F(SceneApiTest, InstanceMovedThroughUpdateInstancesMatchesTheSceneLoadedInThatPose) {
  constexpr uint32_t kSize = 48;
  const std::string path = sharedScene("cornell-box-mcguire/CornellBox-Original.gltf");
  for (bool movable : {true, false}) {
    LoadedScene moved, posed;
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, moved.scene, error)) << error;
    // The instance with the most triangles that is not the room.
    size_t block = 0;
    for (size_t i = 0; i < moved.scene.instances.size(); ++i)
      if (moved.scene.instances[i].name.find("tall") != std::string::npos ||
          moved.scene.instances[i].name.find("Tall") != std::string::npos)
        block = i;
    moved.scene.instances[block].movable = movable;
    posed.scene = moved.scene;
    const glm::mat4 pose = glm::translate(glm::mat4(1.0f), glm::vec3(0.15f, 0.0f, 0.1f)) *
                           glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0, 1, 0)) *
                           moved.scene.instances[block].worldFromObject;
    posed.scene.instances[block].worldFromObject = pose;
    moved.upload(ctx);
    posed.upload(ctx);
    moved.scene.instances[block].worldFromObject = pose;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordUpdateOrFail(ctx, cmd, moved.scene, moved.gpu); });
    engine::ReferenceSettings settings;
    settings.seed = 7;
    const engine::ReferenceImages a = render(moved, kSize, kSize, settings, 8);
    const engine::ReferenceImages b = render(posed, kSize, kSize, settings, 8);
    size_t differ = 0;
    double diff = 0.0, sum = 0.0;
    for (size_t i = 0; i < a.final.pixels.size(); ++i) {
      differ += a.final.pixels[i] != b.final.pixels[i];
      diff += std::fabs(double(a.final.pixels[i]) - b.final.pixels[i]);
      sum += std::fabs(double(b.final.pixels[i]));
    }
    std::printf("%s block: %zu of %zu values differ, relative L1 %.2e\n", movable ? "movable" : "merged", differ,
                a.final.pixels.size(), diff / sum);
    if (movable) {
      EXPECT_EQ(differ, 0u);
    }
    // Merged: the same geometry traced through another BVH; a path that grazes
    // an edge may go the other way, nothing more.
    EXPECT_LT(diff / sum, 0.01);
    // And the block really moved: the image differs from the unmoved scene's.
    LoadedScene still;
    ASSERT_NO_FATAL_FAILURE(load(path, still));
    const engine::ReferenceImages c = render(still, kSize, kSize, settings, 8);
    double moveDiff = 0.0;
    for (size_t i = 0; i < c.final.pixels.size(); ++i)
      moveDiff += std::fabs(double(c.final.pixels[i]) - b.final.pixels[i]);
    EXPECT_GT(moveDiff / sum, 0.05) << "the pose should change the picture";
  }
}

// The CPU BVH (Embree) is built only for the compute traversal: a ray-query scene holds no BVH and says
// so (SceneDesc::hasComputeBvh), a module asked to trace it with the compute traversal is a named error,
// and SceneCreateDesc::bothTraversals builds both.
TEST_F(SceneApiTest, RayQueryScenesBuildNoCpuBvhUnlessAskedForBoth) {
  if (!ctx.rayQuery) GTEST_SKIP() << "the device has no ray queries";
  Quad q;
  gi::Scene* rayQueryOnly = nullptr;
  gi::Scene* both = nullptr;
  gi::SceneCreateDesc desc = createDesc();
  desc.traversal = gi::Traversal::RayQuery;
  gi::Error e;
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::createScene(desc, q.contents(), cmd, rayQueryOnly); });
  ASSERT_FALSE(e) << e.message;
  desc.bothTraversals = true;
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::createScene(desc, q.contents(), cmd, both); });
  ASSERT_FALSE(e) << e.message;
  EXPECT_FALSE(gi::sceneDesc(rayQueryOnly).hasComputeBvh);
  EXPECT_TRUE(rayQueryOnly->bvh.bottomNodes.empty() && rayQueryOnly->bvh.topNodes.empty()) << "no CPU BVH";
  EXPECT_TRUE(gi::sceneDesc(both).hasComputeBvh);
  EXPECT_FALSE(both->bvh.bottomNodes.empty());
  EXPECT_LT(rayQueryOnly->gpu.memory.used, both->gpu.memory.used);
  gi::ModuleDesc module;
  module.getInstanceProcAddr = vkGetInstanceProcAddr;
  module.instance = ctx.instance;
  module.physicalDevice = ctx.physicalDevice;
  module.device = ctx.device;
  module.width = module.height = 8;
  module.scene = gi::sceneDesc(rayQueryOnly);
  module.scene.traversal = gi::Traversal::Compute;
  gi::Module* m = nullptr;
  e = gi::create(module, gi::Settings{}, m);
  EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange);
  EXPECT_NE(e.message.find("built for ray queries alone"), std::string::npos) << e.message;
  EXPECT_EQ(m, nullptr);
  module.scene = gi::sceneDesc(both);
  module.scene.traversal = gi::Traversal::Compute;
  ASSERT_FALSE(gi::create(module, gi::Settings{}, m));
  gi::destroy(m);
  gi::destroyScene(rayQueryOnly);
  gi::destroyScene(both);
}

// SceneCreateDesc::deviceMemory: every byte the scene holds (tables, BVH, textures, acceleration
// structures where ray queries are on, their device-address memory included) comes from the engine's
// allocator, the scene allocates no block of its own, the reference renders bit for bit as from the
// scene's own memory, and destroyScene frees every slice.
TEST_F(SceneApiTest, AnEnginesAllocatorHoldsEveryByteOfTheScene) {
  const std::string path = sharedScene("cornell-box-mcguire/CornellBox-Original.gltf");
  EngineDeviceMemory engineMemory(ctx);  // outlives the scene it holds
  LoadedScene own, engineOwned;
  ASSERT_NO_FATAL_FAILURE(load(path, own));
  std::string error;
  ASSERT_TRUE(engine::loadSceneForRendering(path, engineOwned.scene, error)) << error;
  engineOwned.upload(ctx, engineMemory.callbacks());
  const gi::vk::MemoryArena& arena = engineOwned.gpu.scene->gpu.memory;
  EXPECT_EQ(arena.allocations, 0u);
  EXPECT_GT(engineMemory.liveBytes, 0u);
  EXPECT_EQ(engineMemory.liveBytes, arena.held);
  EXPECT_EQ(arena.held, arena.used);
  EXPECT_EQ(own.gpu.scene->gpu.memory.used, arena.used) << "the same resources, from another allocator";
  engine::ReferenceSettings settings;
  settings.seed = 3;
  const engine::ReferenceImages a = render(own, 32, 32, settings, 4);
  const engine::ReferenceImages b = render(engineOwned, 32, 32, settings, 4);
  EXPECT_EQ(a.final.pixels, b.final.pixels);
  engineOwned.release();
  own.release();
  EXPECT_EQ(engineMemory.liveBytes, 0u);
  EXPECT_EQ(engineMemory.requests, engineMemory.frees);
  EXPECT_TRUE(engineMemory.error.empty()) << engineMemory.error;
}

namespace {

// The engine's Cornell box as device buffers in packed encodings: half-float
// positions (stride 8), snorm8 normals interleaved with unorm16 uvs (stride
// 8, uvs at +4), uint16 indices; and the same values decoded on the CPU.
struct PackedCornell {
  engine::Buffer positions, attributes, indices;
  std::vector<float> cpuPositions, cpuNormals, cpuUvs;
  std::vector<uint32_t> cpuIndices;
  std::vector<gi::PrimitiveDesc> primitives;
  std::vector<gi::MaterialDesc> materials;
  std::vector<gi::InstanceDesc> instances;
  std::vector<gi::MeshDesc> deviceMeshes, cpuMeshes;
};

void packCornell(const engine::Context& ctx, const engine::Scene& scene, PackedCornell& out) {
  const size_t vertices = scene.positions.size();
  ASSERT_LT(vertices, 65536u);
  std::vector<uint16_t> halfs, indices16(scene.indices.begin(), scene.indices.end());
  std::vector<uint32_t> attributes;
  for (size_t v = 0; v < vertices; ++v) {
    const glm::vec3 p = scene.positions[v], n = scene.normals[v];
    const glm::vec2 uv = scene.uvs.empty() ? glm::vec2(float(v % 7) / 7.0f, float(v % 5) / 5.0f) : scene.uvs[v];
    for (int k = 0; k < 3; ++k) halfs.push_back(glm::packHalf1x16(p[k]));
    halfs.push_back(0);
    attributes.push_back(glm::packSnorm4x8(glm::vec4(n, 0.0f)));
    attributes.push_back(glm::packUnorm2x16(glm::clamp(uv, 0.0f, 1.0f)));
    for (int k = 0; k < 3; ++k) out.cpuPositions.push_back(glm::unpackHalf1x16(halfs[4 * v + size_t(k)]));
    const glm::vec4 decoded = glm::unpackSnorm4x8(attributes[2 * v]);
    const float length = std::sqrt(decoded.x * decoded.x + decoded.y * decoded.y + decoded.z * decoded.z);
    for (int k = 0; k < 3; ++k) out.cpuNormals.push_back(decoded[k] / length);
    const glm::vec2 uvDecoded = glm::unpackUnorm2x16(attributes[2 * v + 1]);
    out.cpuUvs.insert(out.cpuUvs.end(), {uvDecoded.x, uvDecoded.y});
  }
  if (indices16.size() % 2) indices16.push_back(0);  // read in whole words
  out.cpuIndices = scene.indices;
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  std::string error;
  out.positions = engine::createBufferWithData(ctx, halfs.data(), halfs.size() * 2, usage, error);
  out.attributes = engine::createBufferWithData(ctx, attributes.data(), attributes.size() * 4, usage, error);
  out.indices = engine::createBufferWithData(ctx, indices16.data(), indices16.size() * 2, usage, error);
  ASSERT_EQ(error, "");
  for (const engine::Primitive& p : scene.primitives)
    out.primitives.push_back({p.firstIndex, p.indexCount, p.vertexOffset, p.vertexCount, p.material});
  for (const engine::Material& m : scene.materials) {
    gi::MaterialDesc d;
    for (int k = 0; k < 4; ++k) d.baseColor[k] = m.baseColor[k];
    for (int k = 0; k < 3; ++k) d.emissive[k] = m.emission[k];
    d.metallic = 0.0f;
    out.materials.push_back(d);
  }
  for (const engine::Instance& inst : scene.instances) {
    gi::InstanceDesc d;
    d.mesh = inst.mesh;
    std::memcpy(d.worldFromObject, &inst.worldFromObject[0][0], sizeof(d.worldFromObject));
    out.instances.push_back(d);
  }
  for (const engine::Mesh& mesh : scene.meshes) {
    gi::MeshDesc d;
    d.vertexCount = uint32_t(vertices);
    d.indexCount = uint32_t(scene.indices.size());
    d.primitives = std::span(out.primitives).subspan(mesh.firstPrimitive, mesh.primitiveCount);
    gi::MeshDesc c = d;
    d.device.positions = {out.positions.address, VK_FORMAT_R16G16B16A16_SFLOAT, 0};
    d.device.normals = {out.attributes.address, VK_FORMAT_R8G8B8A8_SNORM, 8};
    d.device.uvs = {out.attributes.address + 4, VK_FORMAT_R16G16_UNORM, 8};
    d.device.indices = out.indices.address;
    d.device.indexType = VK_INDEX_TYPE_UINT16;
    out.deviceMeshes.push_back(d);
    c.positions = out.cpuPositions.data();
    c.normals = out.cpuNormals.data();
    c.uvs = out.cpuUvs.data();
    c.indices = out.cpuIndices.data();
    out.cpuMeshes.push_back(c);
  }
}

gi::SceneContents cornellContents(PackedCornell& p, bool device) {
  gi::SceneContents c;
  c.meshes = device ? p.deviceMeshes : p.cpuMeshes;
  c.materials = p.materials;
  c.instances = p.instances;
  return c;
}

}  // namespace

// The engine's own device buffers in packed encodings decode to the values
// the CPU decodes (positions and indices exactly, normals and uvs to float
// rounding), through createScene's read-back and finishSceneUpload's build;
// bad streams are named errors at createScene, bad indices (seen only after
// the read-back) at finishSceneUpload.
TEST_F(SceneApiTest, DeviceBufferMeshesDecodeAsTheirCpuValues) {
  LoadedScene loaded;
  std::string error;
  ASSERT_TRUE(
      engine::loadSceneForRendering(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), loaded.scene, error))
      << error;
  PackedCornell p;
  ASSERT_NO_FATAL_FAILURE(packCornell(ctx, loaded.scene, p));
  gi::Scene* device = nullptr;
  gi::Scene* cpu = nullptr;
  ASSERT_FALSE(create(cornellContents(p, true), device));
  EXPECT_FALSE(gi::sceneBuilt(device));
  EXPECT_EQ(gi::sceneDesc(device).set, VK_NULL_HANDLE);
  gi::Error e;
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::finishSceneUpload(device, cmd); });
  ASSERT_FALSE(e) << e.message;
  EXPECT_TRUE(gi::sceneBuilt(device));
  ASSERT_FALSE(create(cornellContents(p, false), cpu));
  const gi::PackedScene& a = device->packed;
  const gi::PackedScene& b = cpu->packed;
  ASSERT_EQ(a.positions.size(), b.positions.size());
  EXPECT_TRUE(a.positions == b.positions);
  EXPECT_TRUE(a.indices == b.indices);  // Morton order follows from equal positions
  float normalError = 0.0f, uvError = 0.0f;
  for (size_t v = 0; v < a.normals.size(); ++v) {
    normalError = std::max(normalError, glm::length(a.normals[v] - b.normals[v]));
    uvError = std::max(uvError, glm::length(a.uvs[v] - b.uvs[v]));
  }
  std::printf("device-buffer decode: %zu vertices, max |normal difference| %.2e, max |uv difference| %.2e\n",
              a.normals.size(), normalError, uvError);
  EXPECT_LE(normalError, 1e-6f);
  EXPECT_LE(uvError, 1e-6f);
  const gi::SceneDesc da = gi::sceneDesc(device), db = gi::sceneDesc(cpu);
  EXPECT_EQ(da.hasEmissiveTriangles, db.hasEmissiveTriangles);
  EXPECT_EQ(da.extent, db.extent);
  EXPECT_EQ(gi::sceneInfo(device).triangles, gi::sceneInfo(cpu).triangles);
  gi::destroyScene(device);
  gi::destroyScene(cpu);

  struct Case {
    const char* what;
    void (*spoil)(gi::MeshDesc&);
    const char* field;
  };
  const Case cases[] = {
      {"unlisted format", [](gi::MeshDesc& m) { m.device.normals.format = VK_FORMAT_R8G8B8A8_UNORM; },
       "contents.meshes[0].device.normals.format"},
      {"stride below the format", [](gi::MeshDesc& m) { m.device.positions.stride = 4; },
       "device.positions.stride = 4"},
      {"misaligned address", [](gi::MeshDesc& m) { m.device.uvs.address += 2; }, "multiples of 4 bytes"},
      {"CPU arrays as well", [](gi::MeshDesc& m) { m.normals = reinterpret_cast<const float*>(&m); }, "both given"},
      {"no index address", [](gi::MeshDesc& m) { m.device.indices = 0; }, "device.indices"},
  };
  for (const Case& c : cases) {
    std::vector<gi::MeshDesc> meshes = p.deviceMeshes;
    c.spoil(meshes[0]);
    gi::SceneContents contents = cornellContents(p, true);
    contents.meshes = meshes;
    gi::Scene* scene = nullptr;
    e = create(contents, scene);
    EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange) << c.what;
    EXPECT_NE(e.message.find(c.field), std::string::npos) << c.what << ": " << e.message;
    EXPECT_EQ(scene, nullptr) << c.what;
  }
  // An index past its primitive's vertices is found once read back.
  std::vector<gi::PrimitiveDesc> tooFew = p.primitives;
  tooFew[0].vertexCount = 1;
  std::vector<gi::MeshDesc> meshes = p.deviceMeshes;
  meshes[0].primitives = std::span(tooFew).subspan(0, meshes[0].primitives.size());
  gi::SceneContents contents = cornellContents(p, true);
  contents.meshes = meshes;
  gi::Scene* scene = nullptr;
  ASSERT_FALSE(create(contents, scene));
  submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::finishSceneUpload(scene, cmd); });
  EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange);
  EXPECT_NE(e.message.find("gi::finishSceneUpload: contents.meshes[0].primitives[0]: index"), std::string::npos)
      << e.message;
  EXPECT_FALSE(gi::sceneBuilt(scene));
  gi::destroyScene(scene);
  for (engine::Buffer* buffer : {&p.positions, &p.attributes, &p.indices}) engine::destroyBuffer(ctx, *buffer);
}
