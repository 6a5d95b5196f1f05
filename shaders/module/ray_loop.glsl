// The one ray loop of a path program. trace.glsl says why a program traces
// through one giTrace call: here every ray of the program's task is traced,
// every closest hit becomes a shading point and every NEE asked for runs its
// shadow rays, each written once, so the traversal, the hit's surface and
// NEE's light sampling are compiled once per program whatever the task does.
//
// Include after defining the task: a struct GiTask (a state machine over the
// program's work) and
//   uint giTaskNext(inout GiTask task, out GiRay ray, out GiNeeRequest nee)
//       returns GI_STEP_TRACE (trace `ray`), GI_STEP_NEE (NEE as `nee` says),
//       GI_STEP_WAIT (nothing this turn) or GI_STEP_DONE (lights.glsl);
//   void giTaskTakeHit(inout GiTask task, GiHit hit, GiSurface s)
//       the hit of the ray it gave; `s` is its shading point where the ray
//       was a closest-hit ray and hit (undefined otherwise);
//   void giTaskTakeNee(inout GiTask task, vec3 light, GiRng rng)
//       NEE's reflected light towards nee.V and the random state after it.
// Each of the three is called at one place below, so the task's own code is
// compiled once too, provided it calls each of its parts at one place.
//
// Lanes in step: a subgroup runs its lanes as one SIMD vector, so an
// iteration costs every part of the loop that any lane needs. The tasks take
// their next step only while no lane of the subgroup has NEE's rays out, and
// a lane that asks for NEE starts it in the same iteration: an iteration then
// mostly traces and shades either NEE's shadow rays or the tasks' own rays,
// not both under masks. (Left to drift apart, lanes made the loop much slower
// than the nested loops it replaced; kept in step it runs as fast.) A task
// whose work comes in parts (AAF's samples) can wait (GI_STEP_WAIT) for the
// subgroup to start the next part together.
#ifndef GI_RAY_LOOP_GLSL
#define GI_RAY_LOOP_GLSL
#extension GL_KHR_shader_subgroup_vote : require
#include "lights.glsl"

void giRunTask(inout GiTask task) {
  GiNeeRequest at;
  GiNee nee = giNeeStart(GI_NO_RESERVOIR);
  bool neeActive = false;     // NEE's shadow rays are this lane's business now
  bool finishPending = false; // NEE's last light gave no ray: hand its light over next iteration
  bool done = false;
  GiRay ray;
  bool tracing = false, shadow = false;  // the ray this iteration traces, and whether it is NEE's
  for (;;) {
    GiHit hit = giNoHit();
    if (tracing) hit = giTrace(ray);
    bool finishNee = finishPending;
    finishPending = false;
    if (tracing && shadow) {
      giNeeTakeHit(nee, hit);
      finishNee = giNeeComplete(nee);  // its last ray: done now
    }
    if (tracing && !shadow) {
      GiSurface s;
      if (!ray.anyHit && hit.t >= 0.0) s = giSurfaceFromHit(hit, ray.direction);
      giTaskTakeHit(task, hit, s);
    }
    if (finishNee) {
      neeActive = false;
      giTaskTakeNee(task, nee.light, at.rng);
    }
    tracing = false;
    // The tasks take their next step only while no lane of the subgroup has NEE's rays out: lanes
    // keep in step, so an iteration mostly shades NEE's rays or the tasks', not both under a mask.
    if (!subgroupAny(neeActive)) {
      if (!done) {
        const uint step = giTaskNext(task, ray, at);
        done = step == GI_STEP_DONE;
        tracing = step == GI_STEP_TRACE;
        shadow = false;
        if (step == GI_STEP_NEE) {
          nee = giNeeStart(at.reservoir);
          neeActive = true;
        }
      }
      if (subgroupAll(done)) break;
    }
    // NEE's next light, at once for a lane that has just asked for NEE (a light that gives no ray
    // leaves the lane idle for this iteration).
    if (neeActive) {
      tracing = giNeeNextRay(nee, at.s, at.b, at.V, at.withMis, at.rng, ray);
      shadow = tracing;
      finishPending = !tracing && giNeeComplete(nee);
    }
  }
}

#endif
