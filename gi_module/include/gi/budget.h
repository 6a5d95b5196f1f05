// Budget mode: hold the module's GPU time per frame near a target by steering
// Settings::rayBudget from the measured time and rays of the last frame.
// Raise the method's quality knob (spp, or μ for AAF) to the most you would
// accept; the budget then lowers what is traced until the frame fits. Methods
// whose cost is whole paths per pixel cannot go below 1 spp.
#pragma once
#include <cstdint>

#include "gi/gi.h"

namespace gi {

struct BudgetController {
  double targetMs = 16.0;       // the module's GPU time to hold per frame, ms (> 0)
  double damping = 0.6;         // exponent of each correction, (0, 1]: 1 jumps straight to the estimate
  uint64_t minRays = 1u << 10;  // never ask for fewer rays per frame than this
  uint64_t maxRays = 1ull << 34;
  uint64_t rayBudget = 0;  // the budget last returned (0 = not started: unlimited)
};

// From the stats of the last completed frame: the ray budget for the next
// frame's settings. Frames without measured time or rays keep the budget.
uint64_t updateBudget(BudgetController& controller, const FrameStats& lastFrame);

}  // namespace gi
