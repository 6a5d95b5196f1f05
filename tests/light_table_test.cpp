// The punctual-light table the shaders read (scene_tables.cpp's lightTable): directional lights first,
// each light's power cdf, and LIGHT_SAMPLER_TREE's tree over the point and spot lights, on the CPU.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "scene/scene_tables.h"

namespace {

// `count` lights of every type at random places and brightnesses, one in `blackEvery` black.
std::vector<gi::LightDesc> randomLights(uint32_t count, uint32_t blackEvery) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<gi::LightDesc> lights(count);
  for (uint32_t i = 0; i < count; ++i) {
    gi::LightDesc& l = lights[i];
    l.type = i % 7 == 3 ? gi::LightType::Directional : i % 5 == 1 ? gi::LightType::Spot : gi::LightType::Point;
    for (int k = 0; k < 3; ++k) {
      l.position[k] = 20.0f * u(rng) - 10.0f;
      l.intensity[k] = i % blackEvery == 0 ? 0.0f : 5.0f * u(rng);
    }
  }
  return lights;
}

}  // namespace

TEST(LightTable, DirectionalLightsComeFirstAndTheCdfFollowsThePower) {
  const std::vector<gi::LightDesc> lights = randomLights(300, 11);
  const gi::LightTable t = gi::lightTable(lights, 20.0f, 4);
  ASSERT_EQ(t.lights.size(), lights.size());
  uint32_t directional = 0;
  for (const gi::LightDesc& l : lights) directional += l.type == gi::LightType::Directional;
  EXPECT_EQ(t.directionalCount, directional);
  for (size_t i = 0; i < t.lights.size(); ++i)
    EXPECT_EQ(t.lights[i].type == gpu::PUNCTUAL_DIRECTIONAL, i < directional) << "light " << i;
  // Black lights are never picked (their step is 0); the others' steps are their share of the power.
  float previous = 0.0f;
  for (size_t i = 0; i < t.lights.size(); ++i) {
    const float step = t.lights[i].cdf - previous;
    EXPECT_GE(step, 0.0f) << "light " << i;
    if (t.lights[i].intensity == glm::vec3(0.0f)) EXPECT_EQ(step, 0.0f) << "black light " << i;
    else EXPECT_GT(step, 0.0f) << "light " << i;
    previous = t.lights[i].cdf;
  }
  EXPECT_EQ(t.lights.back().cdf, 1.0f);
  // Two point lights, one twice as bright: chances 1/3 and 2/3.
  std::vector<gi::LightDesc> two(2);
  two[1].intensity[0] = two[1].intensity[1] = two[1].intensity[2] = 2.0f;
  const gi::LightTable pair = gi::lightTable(two, 1.0f, 4);
  EXPECT_NEAR(pair.lights[0].cdf, 1.0f / 3.0f, 1e-6f);
}

TEST(LightTable, TheTreeHoldsEveryPointAndSpotLightOnceWithBoundsAndPowerOfItsChildren) {
  const std::vector<gi::LightDesc> lights = randomLights(1000, 13);
  const gi::LightTable t = gi::lightTable(lights, 20.0f, 4);
  const size_t positional = t.lights.size() - t.directionalCount;
  ASSERT_EQ(t.nodes.size(), 2 * positional - 1);
  std::vector<int> seen(t.lights.size(), 0);
  size_t leaves = 0;
  for (size_t i = 0; i < t.nodes.size(); ++i) {
    const gpu::GpuLightNode& n = t.nodes[i];
    if (n.child & gpu::LIGHT_NODE_LEAF) {
      const uint32_t light = n.child & ~gpu::LIGHT_NODE_LEAF;
      ASSERT_LT(light, t.lights.size());
      ASSERT_GE(light, t.directionalCount) << "a directional light in the tree";
      ++seen[light];
      ++leaves;
      EXPECT_EQ(n.boundsMin, t.lights[light].position);
      EXPECT_EQ(n.boundsMax, t.lights[light].position);
      continue;
    }
    ASSERT_LT(n.child + 1, t.nodes.size());
    EXPECT_GT(n.child, i) << "children follow their parent";
    const gpu::GpuLightNode &a = t.nodes[n.child], &b = t.nodes[n.child + 1];
    EXPECT_EQ(n.boundsMin, glm::min(a.boundsMin, b.boundsMin)) << "node " << i;
    EXPECT_EQ(n.boundsMax, glm::max(a.boundsMax, b.boundsMax)) << "node " << i;
    EXPECT_NEAR(n.power, a.power + b.power, 1e-4f * n.power) << "node " << i;
  }
  EXPECT_EQ(leaves, positional);
  for (size_t i = t.directionalCount; i < t.lights.size(); ++i) EXPECT_EQ(seen[i], 1) << "light " << i;
  // The words the shaders read: the lights, the nodes, the cut, within the buffer's capacity.
  const std::vector<uint32_t> words = gi::lightTableWords(t);
  const size_t used = (t.lights.size() * sizeof(gpu::GpuPunctualLight) + t.nodes.size() * sizeof(gpu::GpuLightNode)) / 4 +
                      t.cut.size();
  EXPECT_EQ(words.size(), (used + 3) / 4 * 4) << "whole 16-byte texels: the shaders read the cut four words at a time";
  EXPECT_EQ(words[used - 1], t.cut.back());
  EXPECT_LE(words.size(), gi::lightTableCapacityWords(lights.size()));
  EXPECT_EQ(gi::lightTableCapacityWords(1) % 4, 0u);
}

// Every light in exactly one subtree of the cut, for cuts from 1 to more subtrees than lights; a cut at
// least as large as the lights is every light on its own.
TEST(LightTable, TheCutsSubtreesHoldEveryLightOnce) {
  const std::vector<gi::LightDesc> lights = randomLights(37, 5);
  for (uint32_t size : {1u, 2u, 4u, 7u, 16u, 64u}) {
    const gi::LightTable t = gi::lightTable(lights, 20.0f, size);
    const size_t positional = t.lights.size() - t.directionalCount;
    EXPECT_EQ(t.cut.size(), std::min<size_t>(size, positional)) << size;
    std::vector<int> seen(t.lights.size(), 0);
    std::vector<uint32_t> stack(t.cut.begin(), t.cut.end());
    while (!stack.empty()) {
      const gpu::GpuLightNode n = t.nodes[stack.back()];
      stack.pop_back();
      if (n.child & gpu::LIGHT_NODE_LEAF) {
        ++seen[n.child & ~gpu::LIGHT_NODE_LEAF];
      } else {
        stack.push_back(n.child);
        stack.push_back(n.child + 1);
      }
    }
    for (size_t i = t.directionalCount; i < t.lights.size(); ++i) EXPECT_EQ(seen[i], 1) << "cut " << size << ", light " << i;
    if (size >= positional) {
      for (uint32_t node : t.cut) EXPECT_TRUE(t.nodes[node].child & gpu::LIGHT_NODE_LEAF) << "cut " << size;
    }
  }
}

TEST(LightTable, OneLightIsALeafRootAndDirectionalOnlyHasNoTree) {
  std::vector<gi::LightDesc> one(1);
  const gi::LightTable t = gi::lightTable(one, 1.0f, 4);
  ASSERT_EQ(t.nodes.size(), 1u);
  EXPECT_EQ(t.nodes[0].child, gpu::LIGHT_NODE_LEAF | 0u);
  std::vector<gi::LightDesc> sun(2);
  for (gi::LightDesc& l : sun) l.type = gi::LightType::Directional;
  EXPECT_TRUE(gi::lightTable(sun, 1.0f, 4).nodes.empty());
  EXPECT_TRUE(gi::lightTable({}, 1.0f, 4).lights.empty());
}
