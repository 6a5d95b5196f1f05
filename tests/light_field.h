// Many point lights over a floor and a wall, for the light-sampling tests
// (light_sampler_test, reservoir_test), and their loading with a chosen
// light sampler.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>

#include "gpu_test.h"
#include "procedural_scene.h"

class LightFieldTest : public GpuTest {
 protected:
  static void loadWith(const std::string& path, uint32_t sampler, LoadedScene& out, uint32_t treeCut = 1) {
    std::string error;
    ASSERT_TRUE(engine::loadSceneForRendering(path, out.scene, error)) << error;
    out.scene.lightSampler = sampler;
    out.scene.lightTreeCut = treeCut;
    out.upload(ctx);
  }
};

// The largest relative difference between the sums of `image` and of `truth` over any 8×8 block (of those
// `truth` lights; its blocks are all lit when `unlit` is null, else counted there).
inline double worstBlockDifference(const engine::FloatImage& image, const engine::FloatImage& truth, uint32_t size,
                                   uint32_t* unlit = nullptr) {
  double worst = 0.0;
  for (uint32_t by = 0; by < size; by += 8)
    for (uint32_t bx = 0; bx < size; bx += 8) {
      double a = 0.0, b = 0.0;
      for (uint32_t y = by; y < by + 8; ++y)
        for (uint32_t x = bx; x < bx + 8; ++x)
          for (uint32_t c = 0; c < 3; ++c) {
            a += truth.at(x, y, c);
            b += image.at(x, y, c);
          }
      if (a > 0.0)
        worst = std::max(worst, std::abs(b - a) / a);
      else if (unlit)
        ++*unlit;
    }
  return worst;
}

// A floor and a wall under `count` point lights whose intensities span 1:40, in rows of 8 over a 4 m by
// 3 m rectangle 1.2 to 1.8 m up; with `block`, a square slab 0.8 m up that shadows part of the floor;
// with `spots`, spot lights instead, with outer cones from 0.3 to 1.2 rad, aimed in turn down, at the wall
// and up (where they light nothing).
inline std::string lightField(uint32_t count, const std::string& name, bool block = false, bool spots = false) {
  testscene::Description d;
  d.quads.push_back({{{-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}}, glm::vec3(0.6f)});
  d.quads.push_back({{{-4, 0, -2}, {4, 0, -2}, {4, 3, -2}, {-4, 3, -2}}, glm::vec3(0.5f, 0.6f, 0.7f)});
  if (block)
    d.quads.push_back(
        {{{-0.5f, 0.8f, 0.5f}, {0.5f, 0.8f, 0.5f}, {0.5f, 0.8f, -0.5f}, {-0.5f, 0.8f, -0.5f}}, glm::vec3(0.4f)});
  const float rows = float(std::max((count - 1) / 8, 1u));
  for (uint32_t i = 0; i < count; ++i) {
    const float x = -2.0f + 4.0f * float(i % 8) / 7.0f, z = -1.5f + 3.0f * float(i / 8) / rows;
    const float brightness = 0.05f + 2.0f * float((i * 7) % count) / float(count);
    testscene::Light light{{x, 1.2f + 0.3f * float(i % 3), z}, glm::vec3(brightness) * 4.0f / float(count)};
    if (spots) {
      light.outerCone = 0.3f + 0.9f * float((i * 5) % count) / float(count);
      const glm::vec3 aims[3] = {{0.0f, -1.0f, 0.1f}, {0.1f, -0.5f, -1.0f}, {0.1f, 1.0f, 0.0f}};
      light.aim = glm::normalize(aims[(i / 2) % 3]);
    }
    d.lights.push_back(light);
  }
  d.eye = {0, 2.5f, 4.5f};
  d.target = {0, 0.5f, -1};
  return testscene::write(d, name);
}
