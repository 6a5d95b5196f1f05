// Budget mode's controller against a model of a frame's cost: a fixed part
// plus a cost per ray, with timing noise. (The real GPU run prints its
// achieved time in sample_game's test; wall-clock time is never asserted.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gi/budget.h"

namespace {

struct CostModel {
  double fixedMs = 3.0;
  double msPerRay = 0.002;    // 0.5 Mrays/s, lavapipe-like
  uint64_t maxRays = 200000;  // what the method traces unconstrained
  uint64_t raysPerSpp = 0;    // > 0: whole paths per pixel (quantised, at least 1 spp)
  uint32_t seed = 1;

  gi::FrameStats frame(uint64_t budget) {
    uint64_t rays = budget == 0 ? maxRays : std::min(budget, maxRays);
    if (raysPerSpp > 0) rays = std::max<uint64_t>(1, rays / raysPerSpp) * raysPerSpp;
    seed = seed * 1664525u + 1013904223u;
    double noise = 1.0 + 0.1 * (double(seed >> 8) / double(1u << 24) - 0.5) * 2.0;  // ±10%
    gi::FrameStats s;
    s.raysTraced = rays;
    s.totalMs = (fixedMs + msPerRay * double(rays)) * noise;
    return s;
  }
};

double medianOfLast(std::vector<double> v, size_t n) {
  v.erase(v.begin(), v.end() - long(n));
  std::nth_element(v.begin(), v.begin() + long(n / 2), v.end());
  return v[n / 2];
}

std::vector<double> run(CostModel model, double targetMs, int frames) {
  gi::BudgetController c;
  c.targetMs = targetMs;
  std::vector<double> ms;
  for (int f = 0; f < frames; ++f) {
    gi::FrameStats s = model.frame(c.rayBudget);
    ms.push_back(s.totalMs);
    gi::updateBudget(c, s);
  }
  return ms;
}

}  // namespace

TEST(Budget, ConvergesWithinTwentyPercentWhenCostIsContinuous) {
  for (double target : {20.0, 100.0, 300.0}) {
    std::vector<double> ms = run(CostModel{}, target, 40);
    EXPECT_NEAR(medianOfLast(ms, 10), target, 0.2 * target) << "target " << target;
  }
}

TEST(Budget, ConvergesWithinTwentyPercentWithWholePathsPerPixel) {
  CostModel model;
  model.raysPerSpp = 10000;  // 20 ms per spp
  std::vector<double> ms = run(model, 100.0, 40);
  EXPECT_NEAR(medianOfLast(ms, 10), 100.0, 20.0);
}

TEST(Budget, StaysAtTheQualityCeilingWhenTheTargetIsGenerous) {
  std::vector<double> ms = run(CostModel{}, 5000.0, 20);
  EXPECT_NEAR(medianOfLast(ms, 5), 403.0, 0.15 * 403.0);  // everything the method wants, no more
}

TEST(Budget, IgnoresFramesWithoutMeasurements) {
  gi::BudgetController c;
  c.rayBudget = 1234;
  gi::FrameStats empty;
  EXPECT_EQ(gi::updateBudget(c, empty), 1234u);
  c.targetMs = std::nan("");
  gi::FrameStats s;
  s.totalMs = 10.0;
  s.raysTraced = 100;
  EXPECT_EQ(gi::updateBudget(c, s), 1234u);
}
