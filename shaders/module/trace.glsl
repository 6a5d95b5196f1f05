// The one trace interface. Every ray in every shader goes through giTrace
// (a GiRay: nearest hit, or any hit for a shadow ray); the backend is ray
// queries, or with GI_TRACE_COMPUTE our BVH (trace_bvh.glsl).
//
// Each call site of giTrace inlines a whole traversal (Mesa inlines every
// function; lavapipe compiles at a program's first dispatch), so a program's
// compile time grows with its call sites, faster than linearly: the path
// programs are written as ray machines (lights.glsl GiNee, path.glsl GiPath,
// hpsf_sentinel.glsl, hpsf_walk.glsl) whose rays all go through one giTrace call
// in the program's main loop. giTraceClosest and giTraceVisible are one-ray
// conveniences for programs that trace a single ray.
// Alpha-masked geometry is non-opaque in the BLAS; its candidates are accepted
// only where the base-colour alpha reaches the material's cutoff.
#ifndef GI_TRACE_GLSL
#define GI_TRACE_GLSL
#include "scene.glsl"

struct GiHit {
  float t;        // < 0: miss
  uint instance;  // index into sceneInstances
  uint geometry;  // absolute geometry index
  uint triangle;  // within the geometry
  vec2 barycentrics;
};

// Rays traced by this invocation; shaders add it to their counters.
uint giRaysTraced = 0u;

// A ray for giTrace: the segment [tMin, tMax] along a unit direction.
struct GiRay {
  vec3 origin;
  float tMin;
  vec3 direction;
  float tMax;
  bool anyHit;  // a shadow ray: any hit ends the search; giTrace's hit then says only hit or miss
};

GiRay giClosestRay(vec3 origin, vec3 direction, float tMin, float tMax) {
  return GiRay(origin, tMin, direction, tMax, false);
}
GiRay giShadowRay(vec3 origin, vec3 direction, float tMax) { return GiRay(origin, 0.0, direction, tMax, true); }

GiHit giNoHit() {
  GiHit hit;
  hit.t = -1.0;
  hit.instance = 0u;
  hit.geometry = 0u;
  hit.triangle = 0u;
  hit.barycentrics = vec2(0.0);
  return hit;
}

bool giAlphaAccepts(uint geometry, uint triangle, vec2 bary) {
  GpuMaterial m = sceneMaterialData(sceneGeometry(geometry).material);
  float alpha = m.baseColor.a;
  if (m.baseColorTexture != NO_TEXTURE) {
    vec2 uv = sceneUv(sceneTriangle(geometry, triangle), giBarycentricWeights(bary));
    alpha *= sceneTexture(m.baseColorTexture, uv).a;
  }
  return alpha >= m.alphaCutoff;
}

#ifdef GI_TRACE_COMPUTE
#include "trace_bvh.glsl"
#else
// Resolves non-opaque candidates of an initialised query.
void giResolveCandidates(rayQueryEXT query) {
  while (rayQueryProceedEXT(query)) {
    if (rayQueryGetIntersectionTypeEXT(query, false) == gl_RayQueryCandidateIntersectionTriangleEXT) {
      uint geometry = sceneInstance(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false)).firstGeometry +
                      rayQueryGetIntersectionGeometryIndexEXT(query, false);
      uint triangle = rayQueryGetIntersectionPrimitiveIndexEXT(query, false);
      if (giAlphaAccepts(geometry, triangle, rayQueryGetIntersectionBarycentricsEXT(query, false)))
        rayQueryConfirmIntersectionEXT(query);
    }
  }
}

GiHit giTrace(GiRay ray) {
  giRaysTraced++;
  rayQueryEXT query;
  // Without alpha-masked geometry every hit is final: let traversal skip the candidate loop.
  uint flags = (ray.anyHit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT) |
               (GI_SCENE_HAS_ALPHA_MASK ? gl_RayFlagsNoneEXT : gl_RayFlagsOpaqueEXT);
  rayQueryInitializeEXT(query, sceneTlas, flags, 0xff, ray.origin, ray.tMin, ray.direction, ray.tMax);
  giResolveCandidates(query);
  GiHit hit = giNoHit();
  if (rayQueryGetIntersectionTypeEXT(query, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    hit.t = rayQueryGetIntersectionTEXT(query, true);
    // TLAS instances are Morton-ordered: the custom index is the instance table's.
    hit.instance = rayQueryGetIntersectionInstanceCustomIndexEXT(query, true);
    hit.geometry = sceneInstance(hit.instance).firstGeometry + rayQueryGetIntersectionGeometryIndexEXT(query, true);
    hit.triangle = rayQueryGetIntersectionPrimitiveIndexEXT(query, true);
    hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(query, true);
  }
  return hit;
}
#endif  // GI_TRACE_COMPUTE

// One-ray conveniences (each call inlines a traversal: see the top of the file).
GiHit giTraceClosest(vec3 origin, vec3 direction, float tMin, float tMax) {
  return giTrace(giClosestRay(origin, direction, tMin, tMax));
}
// True when nothing blocks the segment [tMin, tMax] along the ray.
bool giTraceVisible(vec3 origin, vec3 direction, float tMin, float tMax) {
  return giTrace(GiRay(origin, tMin, direction, tMax, true)).t < 0.0;
}

// Offsets a ray origin off a surface by a few float ULPs along the normal, so
// secondary rays neither re-hit their own triangle nor skip thin geometry, at
// any distance from the origin (Wächter & Binder, Ray Tracing Gems ch. 6).
vec3 giOffsetRay(vec3 p, vec3 n) {
  const float kOrigin = 1.0 / 32.0;
  const float kFloatScale = 1.0 / 65536.0;
  const float kIntScale = 256.0;
  ivec3 offsetInt = ivec3(kIntScale * n);
  vec3 pInt = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -offsetInt.x : offsetInt.x)),
                   intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -offsetInt.y : offsetInt.y)),
                   intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -offsetInt.z : offsetInt.z)));
  return vec3(abs(p.x) < kOrigin ? p.x + kFloatScale * n.x : pInt.x,
              abs(p.y) < kOrigin ? p.y + kFloatScale * n.y : pInt.y,
              abs(p.z) < kOrigin ? p.z + kFloatScale * n.z : pInt.z);
}

#endif
