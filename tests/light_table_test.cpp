// The punctual-light table the shaders read (scene_tables.cpp's lightTable): directional lights first,
// each light's power cdf, and LIGHT_SAMPLER_TREE's tree over the point and spot lights, on the CPU.
#include <gtest/gtest.h>
#include <numbers>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "scene/light_tree.h"
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
    // Spots aimed anywhere, from pencil beams to more than a hemisphere; most downwards, as lamps are.
    const glm::vec3 aim =
        glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) < 0.8f ? -2.0f : 2.0f * u(rng) - 1.0f, u(rng) - 0.5f));
    for (int k = 0; k < 3; ++k) l.direction[k] = aim[k];
    l.outerConeAngle = 0.05f + 2.0f * u(rng);
    l.innerConeAngle = 0.5f * l.outerConeAngle;
  }
  return lights;
}

// The node's sphere holds the point (metres of slack: float rounding).
bool sphereHolds(const gpu::GpuLightNode& n, glm::vec3 p) {
  return glm::length(p - n.centre) <= n.radius * (1.0f + 1e-5f) + 1e-6f;
}

// The node's aim cone holds the direction (unit).
bool coneHolds(const gpu::GpuLightNode& n, glm::vec3 direction) {
  return glm::dot(n.axis, direction) >= n.cosAim - 1e-6f;
}

// Whether the light brings anything to a surface at x facing ng, as giPreparePunctual decides: in front
// of the surface and, for a spot, strictly inside its outer cone; not black.
bool canLight(const gpu::GpuPunctualLight& l, glm::vec3 x, glm::vec3 ng) {
  const glm::vec3 towards = l.position - x;
  if (l.intensity == glm::vec3(0.0f) || !(glm::dot(ng, towards) > 0.0f)) return false;
  return l.type != gpu::PUNCTUAL_SPOT || glm::dot(l.direction, -glm::normalize(towards)) > l.cosOuter;
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
    if (t.lights[i].intensity == glm::vec3(0.0f))
      EXPECT_EQ(step, 0.0f) << "black light " << i;
    else
      EXPECT_GT(step, 0.0f) << "light " << i;
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
      EXPECT_EQ(n.centre, t.lights[light].position);
      EXPECT_EQ(n.radius, 0.0f);
      continue;
    }
    ASSERT_LT(n.child + 1, t.nodes.size());
    EXPECT_GT(n.child, i) << "children follow their parent";
    const gpu::GpuLightNode &a = t.nodes[n.child], &b = t.nodes[n.child + 1];
    for (const gpu::GpuLightNode* c : {&a, &b}) {
      // A child's cone inside its parent's (the spheres: the importance test below).
      const float between = std::acos(std::clamp(glm::dot(n.axis, c->axis), -1.0f, 1.0f));
      EXPECT_LE(std::min(between + std::acos(c->cosAim), std::numbers::pi_v<float>), std::acos(n.cosAim) + 1e-3f)
          << "node " << i;
      EXPECT_LE(n.cosFalloff, c->cosFalloff) << "node " << i;
    }
    EXPECT_NEAR(n.power, a.power + b.power, 1e-4f * n.power) << "node " << i;
  }
  EXPECT_EQ(leaves, positional);
  for (size_t i = t.directionalCount; i < t.lights.size(); ++i) EXPECT_EQ(seen[i], 1) << "light " << i;
  // The words the shaders read: the lights, the nodes, the cut, within the buffer's capacity.
  const std::vector<uint32_t> words = gi::lightTableWords(t);
  const size_t used =
      (t.lights.size() * sizeof(gpu::GpuPunctualLight) + t.nodes.size() * sizeof(gpu::GpuLightNode)) / 4 + t.cut.size();
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
    for (size_t i = t.directionalCount; i < t.lights.size(); ++i)
      EXPECT_EQ(seen[i], 1) << "cut " << size << ", light " << i;
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

// The importance a vertex picks children by never rules out a light that can light it: for random
// surfaces, every ancestor of every light that can light one (in front of it, inside a spot's cone) has
// importance > 0. And it does rule out: spots aimed down give a ceiling above them none.
TEST(LightTable, TheImportanceKeepsEveryLightThatCanLightASurfaceAndDropsSpotsAimedAway) {
  const std::vector<gi::LightDesc> lights = randomLights(300, 1000);
  const gi::LightTable t = gi::lightTable(lights, 20.0f, 1);
  std::vector<uint32_t> parent(t.nodes.size(), 0), leafOf(t.lights.size(), 0);
  for (uint32_t i = 0; i < t.nodes.size(); ++i) {
    const gpu::GpuLightNode& n = t.nodes[i];
    if (n.child & gpu::LIGHT_NODE_LEAF) {
      leafOf[n.child & ~gpu::LIGHT_NODE_LEAF] = i;
      EXPECT_TRUE(coneHolds(n, t.lights[n.child & ~gpu::LIGHT_NODE_LEAF].direction) ||
                  t.lights[n.child & ~gpu::LIGHT_NODE_LEAF].type != gpu::PUNCTUAL_SPOT);
    } else {
      parent[n.child] = parent[n.child + 1] = i;
    }
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  size_t lit = 0, ruledOut = 0;
  for (int sample = 0; sample < 2000; ++sample) {
    const glm::vec3 x(12.0f * u(rng), 12.0f * u(rng), 12.0f * u(rng));
    const glm::vec3 ng = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 1e-3f, 0.0f));
    for (uint32_t light = t.directionalCount; light < t.lights.size(); ++light) {
      if (!canLight(t.lights[light], x, ng)) continue;
      ++lit;
      for (uint32_t node = leafOf[light];; node = parent[node]) {
        ASSERT_TRUE(sphereHolds(t.nodes[node], t.lights[light].position));
        ASSERT_GT(gpu::lightNodeImportance(t.nodes[node], x, ng), 0.0f)
            << "light " << light << " lights x = (" << x.x << ", " << x.y << ", " << x.z << "), ng = (" << ng.x << ", "
            << ng.y << ", " << ng.z << ") but node " << node << " has no importance: centre (" << t.nodes[node].centre.x
            << ", " << t.nodes[node].centre.y << ", " << t.nodes[node].centre.z << "), radius " << t.nodes[node].radius
            << ", axis (" << t.nodes[node].axis.x << ", " << t.nodes[node].axis.y << ", " << t.nodes[node].axis.z
            << "), cosAim " << t.nodes[node].cosAim << "; the light at (" << t.lights[light].position.x << ", "
            << t.lights[light].position.y << ", " << t.lights[light].position.z << ")";
        if (node == 0) break;
      }
    }
    for (const gpu::GpuLightNode& n : t.nodes) ruledOut += gpu::lightNodeImportance(n, x, ng) == 0.0f;
  }
  EXPECT_GT(lit, 10000u);
  EXPECT_GT(ruledOut, 0u);
  // A row of spots 3 m up aimed straight down with 30° cones (the root's sphere 7.5 m round): the floor
  // below sees them, a ceiling 10 m above them (facing down) and a wall 10 m aside (facing them) do not.
  std::vector<gi::LightDesc> spots(16);
  for (size_t i = 0; i < spots.size(); ++i) {
    spots[i].type = gi::LightType::Spot;
    spots[i].position[0] = float(i);
    spots[i].position[1] = 3.0f;
    spots[i].direction[0] = spots[i].direction[2] = 0.0f;
    spots[i].direction[1] = -1.0f;
    spots[i].outerConeAngle = 0.5236f;
  }
  const gi::LightTable row = gi::lightTable(spots, 20.0f, 1);
  EXPECT_GT(gpu::lightNodeImportance(row.nodes[0], glm::vec3(7.5f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)), 0.0f);
  EXPECT_EQ(gpu::lightNodeImportance(row.nodes[0], glm::vec3(7.5f, 13.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f)), 0.0f);
  EXPECT_EQ(gpu::lightNodeImportance(row.nodes[0], glm::vec3(7.5f, 3.0f, 10.0f), glm::vec3(0.0f, 0.0f, -1.0f)), 0.0f);
}

// The union of a cone with itself is that cone, for any axis: acos of a unit vector's dot with itself
// (1 − 2⁻⁵³ for a third of these axes) once made it a full sphere, the union's fallback for axes without a
// plane between them. And a cone holding another is the union as it is.
TEST(LightTable, AConesUnionWithItselfOrOneItHoldsIsItself) {
  for (int i = 0; i < 1000; ++i) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(std::sin(i * 1.3), std::cos(i * 0.7), std::sin(i * 0.11) + 0.2));
    const gi::DirectionCone cone{axis, 0.01 + 0.002 * (i % 100)};
    const gi::DirectionCone same = gi::coneUnion(cone, cone);
    ASSERT_EQ(same.axis, cone.axis) << i;
    ASSERT_EQ(same.angle, cone.angle) << i;
    const gi::DirectionCone wider{axis, cone.angle + 0.1};
    ASSERT_EQ(gi::coneUnion(cone, wider).angle, wider.angle) << i;
  }
}

namespace {
// Radians between two directions, computed here apart from the module's union.
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
// A unit direction perpendicular to the unit `axis`.
glm::dvec3 perpendicular(const glm::dvec3& axis) {
  return glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
}
// Whether every direction on `inner`'s rim (and its axis) lies within `outer` (radians; a rounding's slack).
bool coneHolds(const gi::DirectionCone& outer, const gi::DirectionCone& inner) {
  const glm::dvec3 u = perpendicular(inner.axis), v = glm::cross(inner.axis, u);
  for (int k = 0; k <= 64; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / 64.0;
    const glm::dvec3 d =
        k == 64 ? inner.axis
                : inner.axis * std::cos(inner.angle) + (u * std::cos(phi) + v * std::sin(phi)) * std::sin(inner.angle);
    if (angleBetween(outer.axis, d) > outer.angle + 1e-14) return false;
  }
  return true;
}
}  // namespace

// The union holds both cones and is no wider than the smallest cone round them (half the sum of a's angle, the
// angle between the axes and b's angle) plus its 1e-6 of rounding: for axes in general position, for axes
// 5e-13 rad apart (no plane to turn in: the branch that widens a's axis by the angle between them) and for
// opposite axes (the full sphere, which holds them, wider than the tightest).
TEST(LightTable, AConesUnionHoldsBothAndIsTheTightestRoundThem) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), angle(0.0, 1.5);
  auto randomAxis = [&] {
    glm::dvec3 d;
    do d = glm::dvec3(unit(rng), unit(rng), unit(rng));
    while (glm::dot(d, d) > 1.0 || glm::dot(d, d) < 1e-6);
    return glm::normalize(d);
  };
  for (int i = 0; i < 3000; ++i) {
    const gi::DirectionCone a{randomAxis(), angle(rng)};
    gi::DirectionCone b{randomAxis(), angle(rng)};
    const int kind = i % 3;  // 0: general, 1: nearly parallel, 2: opposite
    if (kind == 1) {
      b.axis = glm::normalize(a.axis + 5e-13 * perpendicular(a.axis));
      b.angle = a.angle + 5e-14;  // neither holds the other
    }
    if (kind == 2) b.axis = -a.axis;
    const gi::DirectionCone u = gi::coneUnion(a, b);
    ASSERT_TRUE(coneHolds(u, a)) << i;
    ASSERT_TRUE(coneHolds(u, b)) << i;
    ASSERT_LE(u.angle, std::numbers::pi) << i;
    const double tightest = std::max({a.angle, b.angle, 0.5 * (a.angle + angleBetween(a.axis, b.axis) + b.angle)});
    if (kind != 2) {
      ASSERT_LE(u.angle, std::min(tightest, std::numbers::pi) + 2e-6) << i;
    }
  }
}
