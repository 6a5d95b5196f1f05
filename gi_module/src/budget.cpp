#include "gi/budget.h"

#include <algorithm>
#include <cmath>

namespace gi {

uint64_t updateBudget(BudgetController& c, const FrameStats& last) {
  if (last.totalMs <= 0.0 || last.raysTraced == 0 || !(c.targetMs > 0.0)) return c.rayBudget;
  // Cost is close to proportional to rays (plus a fixed part for the filters),
  // so scale what the frame traced by (target / measured), damped in log space
  // so timing noise does not make the budget oscillate, and at most 4× a step.
  double ratio = std::clamp(c.targetMs / last.totalMs, 0.25, 4.0);
  double next = double(last.raysTraced) * std::pow(ratio, std::clamp(c.damping, 0.05, 1.0));
  c.rayBudget = uint64_t(std::clamp(next, double(c.minRays), double(c.maxRays)));
  return c.rayBudget;
}

}  // namespace gi
