#version 460
// Box mean whose cost does not depend on the radius: one thread walks a row
// (or a column) of the statistics images (1/s of the render rectangle,
// gifStackSize) keeping a running window sum. Windows are clipped at the
// image border and divided by the pixels they hold, so two passes (rows,
// then columns) give the exact 2-D clipped box mean.
// In place: the means overwrite the line as the thread walks it, and the r
// originals the window still has to drop are kept in a ring (a second stack
// of images would cost 8 rgba32f images, 266 MB at 1920×1080). The sums are
// the same additions in the same order as with a separate destination.
#extension GL_GOOGLE_include_directive : require
#include "filters.glsl"

layout(local_size_x = FILTER_LINE_GROUP) in;
layout(push_constant, scalar) uniform Push { BoxPush pc; };

ivec2 linePixel(int line, int t) { return pc.vertical == 0u ? ivec2(t, line) : ivec2(line, t); }

void main() {
  ivec2 size = gifStackSize(pc.subsample);
  int line = int(gl_GlobalInvocationID.x);
  int lines = pc.vertical == 0u ? size.y : size.x;
  int length = pc.vertical == 0u ? size.x : size.y;
  if (line >= lines) return;
  int r = int(min(pc.radius, GIF_MAX_RADIUS));
  int ringSize = r + 1;  // originals t − r .. t
  vec4 ring[GIF_MAX_RADIUS + 1u];
  for (uint img = 0u; img < pc.imageCount; ++img) {
    vec4 sum = vec4(0.0);
    for (int t = 0; t <= min(r, length - 1); ++t) sum += imageLoad(filterA[img], linePixel(line, t));
    for (int t = 0; t < length; ++t) {
      ring[t % ringSize] = imageLoad(filterA[img], linePixel(line, t));
      int count = min(t + r, length - 1) - max(t - r, 0) + 1;
      imageStore(filterA[img], linePixel(line, t), sum / float(count));
      int add = t + r + 1, drop = t - r;
      if (add < length) sum += imageLoad(filterA[img], linePixel(line, add));
      if (drop >= 0) sum -= ring[drop % ringSize];
    }
  }
}
