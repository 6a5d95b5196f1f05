#include "gi/budget.h"

#include <algorithm>
#include <cmath>

namespace gi {

uint64_t updateBudget(BudgetController& c, const FrameStats& last) {
  if (last.totalMs <= 0.0 || last.raysTraced == 0 || !(c.targetMs > 0.0)) return c.rayBudget;
  // Cost is close to proportional to rays (plus a fixed part for the filters),
  // so scale the budget by (target / measured), damped in log space so timing
  // noise does not make it oscillate, and at most 4× a step. Scaling the
  // budget rather than the rays traced makes the error integrate away where
  // the module traces a fixed fraction more or less than its budget; keeping
  // it within 4× of what was traced stops it winding up at a quality floor
  // or ceiling the module cannot pass.
  double ratio = std::clamp(c.targetMs / last.totalMs, 0.25, 4.0);
  double rays = double(last.raysTraced);
  double base = c.rayBudget > 0 ? double(c.rayBudget) : rays;
  double next = std::clamp(base * std::pow(ratio, std::clamp(c.damping, 0.05, 1.0)), 0.25 * rays, 4.0 * rays);
  c.rayBudget = uint64_t(std::clamp(next, double(c.minRays), double(c.maxRays)));
  return c.rayBudget;
}

}  // namespace gi
