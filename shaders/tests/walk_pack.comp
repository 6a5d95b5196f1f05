#version 460
// The hash map's packed records, through the functions the anhpsf passes use
// (tests/walk_pack_test.cpp): thread i packs walk i into an HgWalkRecord and
// unpacks it again, and blends mean i towards its target `frames` times,
// storing it as HgCell::recent in between (hpsf_resolve.comp's running mean);
// and packs sentinel i's two answers as a cell keeps them and compares them
// (hpsf_validate.comp's check).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "hpsf.glsl"
#include "shared/walk_pack.h"

layout(local_size_x = 64) in;
layout(push_constant, scalar) uniform Push { WpPush pc; };
layout(set = 0, binding = WP_BINDING_WALKS, scalar) buffer Walks { HgWalk walks[]; };
layout(set = 0, binding = WP_BINDING_MEANS, scalar) buffer Means { WpMean means[]; };
layout(set = 0, binding = WP_BINDING_SENTINELS, scalar) buffer Sentinels { WpSentinel sentinels[]; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i < pc.sentinelCount) {
    const WpSentinel s = sentinels[i];
    const uint then = hgPackSentinelSeen(s.distanceThen, s.lightThen, pc.radianceScale);
    sentinels[i].seenThen = then;
    sentinels[i].change = hgSentinelChange(then, hgPackSentinelSeen(s.distanceNow, s.lightNow, pc.radianceScale),
                                           s.cellMean, pc.radianceScale);
  }
  if (i >= pc.count) return;
  walks[i] = hgUnpackWalk(hgPackWalk(walks[i]));
  HgCell c = hgEmptyCell();
  c.recent = hgPackRecent(means[i].start, pc.radianceScale, means[i].key, 0u);
  for (uint frame = 1u; frame <= pc.frames; ++frame) {
    const vec3 mean = mix(hgCellRecent(c, pc.radianceScale), means[i].target, means[i].weight);
    c.recent = hgPackRecent(mean, pc.radianceScale, means[i].key, frame);
  }
  means[i].result = hgCellRecent(c, pc.radianceScale);
}
