#version 460
// Reference path tracer: progressive, unbiased for the bounce limit B
// (bounce accounting in path.glsl). One jittered primary ray per sample.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "path.glsl"
#include "camera.glsl"
#include "shared/path_tracer.h"

layout(local_size_x = PT_GROUP_SIZE, local_size_y = PT_GROUP_SIZE) in;

layout(set = 1, binding = PT_BINDING_CAMERA, scalar) uniform CameraBlock { GpuCamera camera; };
layout(set = 1, binding = PT_BINDING_FINAL, rgba32f) uniform image2D accumFinal;
layout(set = 1, binding = PT_BINDING_DIRECT, rgba32f) uniform image2D accumDirect;
layout(set = 1, binding = PT_BINDING_INDIRECT, rgba32f) uniform image2D accumIndirect;
layout(set = 1, binding = PT_BINDING_ALBEDO_DEPTH, rgba32f) uniform image2D accumAlbedoDepth;
layout(set = 1, binding = PT_BINDING_NORMAL, rgba32f) uniform image2D accumNormal;
layout(set = 1, binding = PT_BINDING_RAY_COUNTER, scalar) buffer RayCounter { uint rayCounter; };
layout(push_constant, scalar) uniform Push { PathTracerPush pc; };

struct PathResult {
  vec3 direct;
  vec3 indirect;       // with the first hit's BSDF
  vec3 indirectDemod;  // with the first hit's BSDF replaced by a white Lambertian
  vec3 albedo;
  vec3 normal;
  float depth;
};

// One sample as a ray task (ray_loop.glsl): the primary ray, then the path from its hit.
struct GiTask {
  PathResult r;
  GiPath path;
  GiRng rng;
  vec3 primaryDirection;
  uint phase;  // 0: the primary ray is next, 1: it is out, 2: the path
};

uint giTaskNext(inout GiTask task, out GiRay ray, out GiNeeRequest nee) {
  if (task.phase == 0u) {
    ray = giClosestRay(camera.position, task.primaryDirection, 0.0, GI_FLT_MAX);
    task.phase = 1u;
    return GI_STEP_TRACE;
  }
  return task.phase == 2u ? giPathNext(task.path, task.rng, ray, nee) : GI_STEP_DONE;
}

void giTaskTakeHit(inout GiTask task, GiHit hit, GiSurface s) {
  if (task.phase == 2u) {
    giPathTakeHit(task.path, hit, s);
    return;
  }
  if (hit.t < 0.0) {
    task.r.direct = giSkyRadiance(task.primaryDirection);  // the background
    return;
  }
  task.r.albedo = s.material.baseColor;
  task.r.normal = s.normal;
  task.r.depth = giViewDepth(camera, s.position);
  task.r.direct = s.material.emission;
  task.path = giPathStart(s, -task.primaryDirection, pc.maxBounces, pc.russianRouletteStart);
  task.phase = 2u;
}

void giTaskTakeNee(inout GiTask task, vec3 light, GiRng rng) {
  task.rng = rng;
  giPathTakeNee(task.path, light, task.rng);
}

#include "ray_loop.glsl"
// The engine's program: its reads are never checked (bounds.glsl).
GI_BOUNDS_UNCHECKED
uint giLightSampler() { return sceneConstants().lightSampler; }  // the reference follows the scene
bool giReservoirsHoldPunctual() { return false; }                // and has no reservoirs
bool giReservoirsHoldEmissive() { return false; }
bool giReservoirsHoldSky() { return false; }
float giReservoirsSkyVisibility() { return 1.0; }

PathResult tracePath(uvec2 pixel, uint sampleIndex) {
  GiTask task;
  task.r.direct = task.r.indirect = task.r.indirectDemod = task.r.albedo = task.r.normal = vec3(0.0);
  task.r.depth = 0.0;
  task.rng = giRngCreate(pixel, sampleIndex, pc.seed, GI_STREAM_REFERENCE);
  vec2 jitter = pc.pixelJitter != 0u ? giRandom2(task.rng) : vec2(0.5);
  task.primaryDirection = giCameraRayDirection(camera, vec2(pixel) + jitter);
  task.phase = 0u;
  giRunTask(task);
  if (task.phase == 2u) {
    task.r.direct += task.path.result.direct;
    task.r.indirect = task.path.result.indirect;
    task.r.indirectDemod = task.path.result.indirectDemod;
  }
  return task.r;
}

// The first dispatch of a render overwrites the sums, so no clear pass is needed.
#define ACCUMULATE(img, p, value) imageStore(img, p, (pc.firstSample == 0u ? vec4(0.0) : imageLoad(img, p)) + (value))

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  bool inside = all(lessThan(pixel, uvec2(camera.imageSize)));
  if (inside) {
    PathResult sum;
    sum.direct = sum.indirect = sum.indirectDemod = sum.albedo = sum.normal = vec3(0.0);
    sum.depth = 0.0;
    for (uint i = 0u; i < pc.samplesPerDispatch; ++i) {
      PathResult r = tracePath(pixel, pc.firstSample + i);
      sum.direct += r.direct;
      sum.indirect += r.indirect;
      sum.indirectDemod += r.indirectDemod;
      sum.albedo += r.albedo;
      sum.normal += r.normal;
      sum.depth += r.depth;
    }
    ivec2 p = ivec2(pixel);
    ACCUMULATE(accumFinal, p, vec4(sum.direct + sum.indirect, 1.0));
    ACCUMULATE(accumDirect, p, vec4(sum.direct, 1.0));
    ACCUMULATE(accumIndirect, p, vec4(sum.indirectDemod, 1.0));
    ACCUMULATE(accumAlbedoDepth, p, vec4(sum.albedo, sum.depth));
    ACCUMULATE(accumNormal, p, vec4(sum.normal, 1.0));
  }
  uint rays = subgroupAdd(inside ? giRaysTraced : 0u);
  if (subgroupElect()) atomicAdd(rayCounter, rays);
}
