// The ray task of a program that traces whole paths from a surface and
// nothing else (raw's trace, the temporal gradients): giTracePathFromSurface
// traces one path through the program's one ray loop (ray_loop.glsl).
#ifndef GI_PATH_TASK_GLSL
#define GI_PATH_TASK_GLSL
#include "path.glsl"

struct GiTask {
  GiPath path;
  GiRng rng;
};
uint giTaskNext(inout GiTask task, out GiRay ray, out GiNeeRequest nee) { return giPathNext(task.path, task.rng, ray, nee); }
void giTaskTakeHit(inout GiTask task, GiHit hit, GiSurface s) { giPathTakeHit(task.path, hit, s); }
void giTaskTakeNee(inout GiTask task, vec3 light, GiRng rng) {
  task.rng = rng;
  giPathTakeNee(task.path, light, task.rng);
}
#include "ray_loop.glsl"

// Call it at one place in a program: each call inlines the ray loop. `reservoir`: vertex 0's (a primary
// hit's), or GI_NO_RESERVOIR.
GiPathSample giTracePathFromSurface(GiSurface vertex0, vec3 V, uint maxBounces, uint russianRouletteStart, uvec2 reservoir,
                                    inout GiRng rng) {
  GiTask task = GiTask(giPathStart(vertex0, V, maxBounces, russianRouletteStart), rng);
  task.path.reservoir = reservoir;
  giRunTask(task);
  rng = task.rng;
  return task.path.result;
}

#endif
