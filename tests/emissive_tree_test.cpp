// The emissive triangles' tree (scene_tables.cpp's emissiveTable, LIGHT_SAMPLER_TREE's pick in
// lights.glsl), on the CPU: every triangle of every emissive primitive keeps an entry in (instance,
// geometry, triangle) order, the tree's leaves are those entries once each, a vertex's chances of the
// leaves (each level's share of the children's importance, walked up from the leaf as giTreeLeafChance
// does) sum to one, and a triangle that can light a vertex is never ruled out.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "scene/scene_tables.h"

namespace {

// `count` small triangles at random places, facing anywhere, one in five black (an emissive primitive of
// its own, excluded), one in seven without area; and a floor that does not emit. Two instances of the mesh.
struct RandomEmitters {
  std::vector<float> positions, normals;
  std::vector<uint32_t> indices;
  std::vector<gi::PrimitiveDesc> primitives;
  std::vector<gi::MaterialDesc> materials;
  gi::MeshDesc mesh;
  gi::InstanceDesc instances[2];

  explicit RandomEmitters(uint32_t count) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    materials.resize(3);
    materials[0].emissive[0] = materials[0].emissive[1] = materials[0].emissive[2] = 1.0f;
    materials[0].emissiveStrength = 3.0f;
    materials[1].emissive[0] = 0.5f;  // a red one
    // materials[2]: black
    for (uint32_t t = 0; t < count; ++t) {
      const glm::vec3 centre(8.0f * u(rng), 3.0f + 2.0f * u(rng), 8.0f * u(rng));
      const glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 1e-3f, 0.0f));
      const glm::vec3 a = glm::normalize(glm::cross(n, glm::vec3(0.3f, 0.5f, 0.8f))), b = glm::cross(n, a);
      const float size = t % 7 == 3 ? 0.0f : 0.05f + 0.3f * (u(rng) + 1.0f);
      const glm::vec3 corners[3] = {centre, centre + size * a, centre + size * b};
      const uint32_t first = uint32_t(positions.size() / 3);
      for (const glm::vec3& p : corners)
        for (int k = 0; k < 3; ++k) {
          positions.push_back(p[k]);
          normals.push_back(n[k]);
        }
      for (uint32_t k = 0; k < 3; ++k) indices.push_back(first + k);
      primitives.push_back({3 * t, 3, 0, 3 * count, t % 5 == 2 ? 2u : t % 3 == 1 ? 1u : 0u});
    }
    mesh.positions = positions.data();
    mesh.normals = normals.data();
    mesh.vertexCount = uint32_t(positions.size() / 3);
    mesh.indices = indices.data();
    mesh.indexCount = uint32_t(indices.size());
    mesh.primitives = primitives;
    instances[1].worldFromObject[12] = 20.0f;  // the second instance 20 m along x
    instances[1].worldFromObject[0] = -1.0f;   // and mirrored: its triangles wind the other way
  }
  gi::SceneContents contents() const {
    gi::SceneContents c;
    c.meshes = {&mesh, 1};
    c.materials = materials;
    c.instances = instances;
    return c;
  }
};

// Whether the triangle (world corners, the side its emission leaves towards: `front`) sends light to x,
// as giPrepareEmissive decides for a point on it: x on the emitting side of its plane.
bool canLight(const glm::vec3 (&v)[3], glm::vec3 front, glm::vec3 x, glm::vec3 ng) {
  const glm::vec3 centre = (v[0] + v[1] + v[2]) / 3.0f;
  return glm::dot(front, x - centre) > 1e-3f && glm::dot(ng, centre - x) > 1e-3f;
}

}  // namespace

TEST(EmissiveTree, EveryEmissiveTriangleHasAnEntryInOrderAndALeafOnce) {
  const RandomEmitters scene(120);
  gi::PackedScene packed;
  ASSERT_EQ(gi::packScene(scene.contents(), packed), "");
  const gi::EmissiveTable t = gi::emissiveTable(packed, scene.instances);
  // Black primitives emit nothing: 120 − 24 a mesh, twice.
  ASSERT_EQ(t.triangles.size(), 2u * 96u);
  ASSERT_EQ(t.pickable(), t.triangles.size());
  ASSERT_EQ(t.nodes.size(), 2 * t.triangles.size() - 1);
  for (size_t k = 1; k < t.triangles.size(); ++k) {
    const gpu::GpuEmissiveTriangle &a = t.triangles[k - 1], &b = t.triangles[k];
    EXPECT_TRUE(a.instance < b.instance ||
                (a.instance == b.instance &&
                 (a.geometry < b.geometry || (a.geometry == b.geometry && a.triangle < b.triangle))))
        << k;
    EXPECT_GE(b.cdf, a.cdf) << k;
  }
  EXPECT_EQ(t.triangles.back().cdf, 1.0f);
  std::vector<uint32_t> leaves(t.triangles.size(), 0);
  for (uint32_t i = 0; i < t.nodes.size(); ++i) {
    const gpu::GpuLightNode& n = t.nodes[i];
    if (n.child & gpu::LIGHT_NODE_LEAF) {
      ++leaves.at(n.child & ~gpu::LIGHT_NODE_LEAF);
    } else {
      EXPECT_EQ(t.nodes[n.child].parent, i);
      EXPECT_EQ(t.nodes[n.child + 1].parent, i);
      EXPECT_NEAR(n.power, t.nodes[n.child].power + t.nodes[n.child + 1].power, 1e-4 * n.power);
    }
    EXPECT_EQ(n.cosFalloff, 0.0f) << "cosine emitters";
  }
  for (uint32_t k = 0; k < leaves.size(); ++k) EXPECT_EQ(leaves[k], 1u) << k;
  // The words the shaders read: each entry's leaf after the nodes.
  const std::vector<uint32_t> words = gi::emissiveTableWords(t);
  const size_t leafWord = t.triangles.size() * 4 + t.nodes.size() * 12;
  for (uint32_t k = 0; k < t.triangles.size(); ++k)
    EXPECT_EQ(t.nodes[words[leafWord + k]].child, gpu::LIGHT_NODE_LEAF | k) << k;
  EXPECT_LE(words.size(), gi::emissiveTableCapacityWords(t.triangles.size()));
}

// For random surfaces: the leaves' chances sum to one wherever any has importance (less what a walk down
// leaves at a node both of whose children have none: none of its triangles can light the surface, and the
// NEE sample brings nothing, as it would have from any of them), and every ancestor of
// a triangle that can light the surface has importance (no triangle the NEE could use is ruled out). And
// the tree does rule out: triangles facing away give many surfaces no importance for them.
TEST(EmissiveTree, TheLeavesChancesSumToOneAndNoTriangleThatCanLightASurfaceIsRuledOut) {
  const RandomEmitters scene(200);
  gi::PackedScene packed;
  ASSERT_EQ(gi::packScene(scene.contents(), packed), "");
  const gi::EmissiveTable t = gi::emissiveTable(packed, scene.instances);
  std::vector<uint32_t> leafOf(t.triangles.size());
  for (uint32_t i = 0; i < t.nodes.size(); ++i)
    if (t.nodes[i].child & gpu::LIGHT_NODE_LEAF) leafOf[t.nodes[i].child & ~gpu::LIGHT_NODE_LEAF] = i;
  // The triangles' world corners and emitting sides, as the shaders see them.
  std::vector<std::array<glm::vec3, 3>> corners(t.triangles.size());
  std::vector<glm::vec3> front(t.triangles.size());
  for (size_t k = 0; k < t.triangles.size(); ++k) {
    const gpu::GpuEmissiveTriangle& e = t.triangles[k];
    const glm::mat4 world = gi::toMat4(scene.instances[e.instance].worldFromObject);
    const gpu::GpuGeometry& g = packed.geometries[e.geometry];
    glm::vec3 n(0.0f);
    for (int c = 0; c < 3; ++c) {
      const uint32_t vertex = g.vertexOffset + packed.indices[g.firstIndex + 3 * e.triangle + c];
      corners[k][c] = glm::vec3(world * glm::vec4(packed.positions[vertex], 1.0f));
      n += glm::transpose(glm::inverse(glm::mat3(world))) * packed.normals[vertex];
    }
    const glm::vec3 geometric = glm::cross(corners[k][1] - corners[k][0], corners[k][2] - corners[k][0]);
    front[k] = glm::dot(geometric, n) >= 0.0f ? geometric : -geometric;
  }
  auto chanceOf = [&](uint32_t leaf, glm::vec3 x, glm::vec3 ng) {
    double chance = 1.0;
    for (uint32_t node = leaf; node != 0; node = t.nodes[node].parent) {
      const uint32_t first = t.nodes[t.nodes[node].parent].child;
      const float a = gpu::lightNodeImportance(t.nodes[first], x, ng);
      const float b = gpu::lightNodeImportance(t.nodes[first + 1], x, ng);
      if (!(a + b > 0.0f)) return 0.0;
      const float p = a / (a + b);
      chance *= node == first ? p : 1.0f - p;
    }
    return chance;
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  size_t lit = 0, ruledOut = 0, surfaces = 0;
  double deadEndMass = 0.0;
  for (int sample = 0; sample < 400; ++sample) {
    const glm::vec3 x(14.0f * u(rng) + 10.0f, 3.0f + 4.0f * u(rng), 10.0f * u(rng));
    const glm::vec3 ng = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 1e-3f, 0.0f));
    double sum = 0.0, deadEnds = 0.0;
    for (uint32_t i = 0; i < t.nodes.size(); ++i) {
      const gpu::GpuLightNode& n = t.nodes[i];
      if (!(n.child & gpu::LIGHT_NODE_LEAF) && gpu::lightNodeImportance(t.nodes[n.child], x, ng) == 0.0f &&
          gpu::lightNodeImportance(t.nodes[n.child + 1], x, ng) == 0.0f)
        deadEnds += chanceOf(i, x, ng);
    }
    for (uint32_t k = 0; k < t.triangles.size(); ++k) {
      const double chance = chanceOf(leafOf[k], x, ng);
      sum += chance;
      const glm::vec3 v[3] = {corners[k][0], corners[k][1], corners[k][2]};
      const bool area = glm::length(glm::cross(v[1] - v[0], v[2] - v[0])) > 0.0f;
      if (area && canLight(v, front[k], x, ng)) {
        ++lit;
        EXPECT_GT(chance, 0.0) << "triangle " << k << " lights x = (" << x.x << ", " << x.y << ", " << x.z << ")";
      }
      ruledOut += chance == 0.0;
    }
    if (sum > 0.0) {
      ++surfaces;
      EXPECT_NEAR(sum + deadEnds, 1.0, 1e-5) << "sample " << sample;
      deadEndMass += deadEnds;
    }
  }
  std::printf("%zu surfaces, %zu triangle-surface pairs lit, %zu ruled out; mean chance of a dead end %.3f\n", surfaces,
              lit, ruledOut, deadEndMass / double(surfaces));
  EXPECT_GT(surfaces, 300u);
  EXPECT_GT(lit, 10000u);
  EXPECT_GT(ruledOut, 10000u);
}
