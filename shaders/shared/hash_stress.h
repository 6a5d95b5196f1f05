// The hash map's test workload (hash_stress.comp; tests/hash_grid_test.cpp, module_bounds_test.cpp): its
// push constants and modes, once for the shader and the tests.
#ifndef GI_HASH_STRESS_H
#define GI_HASH_STRESS_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST HG_STRESS_INSERT = 0u;  // thread i adds `count` samples to key keyBase + i mod keyCount (0: only finds)
GPU_CONST HG_STRESS_EVICT = 1u;   // thread i evicts key keyBase + i (as resolve does)
GPU_CONST HG_STRESS_TIDY = 2u;    // thread i tidies slot i (as resolve does for tombstones)
GPU_CONST HG_STRESS_CLAIM = 3u;   // thread i gives slot i to the key that asked for it (as hpsf_claim.comp does)

struct HgStressPush {
  uint capacity;   // cells the shader is told the map has
  uint window;     // probing window
  uint keyCount;
  uint repeats;
  uint mode;       // HG_STRESS_*
  uint keyBase;
  uint sameIndex;  // 1: every key starts probing at slot 0 (one long chain)
  uint count;      // samples each insert adds
  uint deferred;   // 1: a missing key asks for a slot (HgPush::deferredClaims), which HG_STRESS_CLAIM gives
};
GPU_ASSERT_SIZE(HgStressPush, 36);

GPU_NAMESPACE_END

#endif
