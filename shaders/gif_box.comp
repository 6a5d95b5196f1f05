#version 460
// Box mean whose cost does not depend on the radius: one thread walks a row
// (or a column) keeping a running window sum. Windows are clipped at the
// image border and divided by the pixels they hold, so two passes (rows,
// then columns) give the exact 2-D clipped box mean.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_LINE_GROUP) in;
layout(push_constant, scalar) uniform Push { BoxPush pc; };

vec4 loadSource(uint img, ivec2 p) { return pc.vertical == 0u ? imageLoad(filterA[img], p) : imageLoad(filterB[img], p); }
void storeDestination(uint img, ivec2 p, vec4 v) {
  if (pc.vertical == 0u) imageStore(filterB[img], p, v);
  else imageStore(filterA[img], p, v);
}

void main() {
  ivec2 size = filterSize();
  int line = int(gl_GlobalInvocationID.x);
  int lines = pc.vertical == 0u ? size.y : size.x;
  int length = pc.vertical == 0u ? size.x : size.y;
  if (line >= lines) return;
  int r = int(pc.radius);
  for (uint img = 0u; img < pc.imageCount; ++img) {
    vec4 sum = vec4(0.0);
    for (int t = 0; t <= min(r, length - 1); ++t) sum += loadSource(img, pc.vertical == 0u ? ivec2(t, line) : ivec2(line, t));
    for (int t = 0; t < length; ++t) {
      int count = min(t + r, length - 1) - max(t - r, 0) + 1;
      storeDestination(img, pc.vertical == 0u ? ivec2(t, line) : ivec2(line, t), sum / float(count));
      int add = t + r + 1, drop = t - r;
      if (add < length) sum += loadSource(img, pc.vertical == 0u ? ivec2(add, line) : ivec2(line, add));
      if (drop >= 0) sum -= loadSource(img, pc.vertical == 0u ? ivec2(drop, line) : ivec2(line, drop));
    }
  }
}
