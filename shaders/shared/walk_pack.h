// The hash map's packed records under test (walk_pack.comp; tests/walk_pack_test.cpp): anhpsf's
// continued path as it is stored between frames (HgWalkRecord), a cell's recent mean (HgCell::recent) and
// what its sentinel saw (HgCell::sentinelSeen), their bindings and push constants, once for the shader and
// the test.
#ifndef GI_WALK_PACK_H
#define GI_WALK_PACK_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST WP_BINDING_WALKS = 0;   // HgWalk[count]: in, then the same walks after hgPackWalk and hgUnpackWalk
GPU_CONST WP_BINDING_MEANS = 1;   // WpMean[count]: a running mean blended `frames` times, stored packed each time
GPU_CONST WP_BINDING_SENTINELS = 2;  // WpSentinel[sentinelCount]: two answers of a sentinel, packed and compared

struct WpMean {
  vec3 start;    // the mean before the first frame
  float weight;  // each frame blends weight · (target − mean) in, as resolve does with its window's weight
  vec3 target;   // every frame's mean
  uint key;      // the cell's key (the dither's seed with the frame)
  vec3 result;   // out: the mean after `frames` frames, as a reader unpacks it
  uint pad0;
};
GPU_ASSERT_SIZE(WpMean, 48);

struct WpSentinel {
  float distanceThen;  // metres, < 0: missed (what the sentinel saw when it was stored)
  float lightThen;     // NEE luminance at the hit
  float distanceNow;   // the same, re-traced
  float lightNow;
  float cellMean;      // the cell's mean luminance
  uint seenThen;       // out: hgPackSentinelSeen(distanceThen, lightThen)
  float change;        // out: hgSentinelChange(then, now, cellMean)
  uint pad0;
};
GPU_ASSERT_SIZE(WpSentinel, 32);

struct WpPush {
  uint count;
  uint frames;
  float radianceScale;
  uint sentinelCount;
};
GPU_ASSERT_SIZE(WpPush, 16);

GPU_NAMESPACE_END

#endif
