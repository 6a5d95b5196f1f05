// A ray hit turned into a shading point: world position, oriented normals,
// material. Surfaces reflect on both sides; emission is one-sided (the side
// the interpolated vertex normals point to).
#ifndef GI_SURFACE_GLSL
#define GI_SURFACE_GLSL
#include "trace.glsl"

struct GiSurface {
  vec3 position;         // world, metres
  vec3 normal;           // shading normal, on the side the ray came from
  vec3 geometricNormal;  // triangle normal, same side as `normal`
  bool frontFace;        // the ray hit the emitting side
  vec2 uv;
  MaterialSample material;
};

// Meijer's filter criterion: a vertex whose material has a diffuse lobe
// (every material but a pure metal). Its albedo does not matter: the filters
// keep demodulated light, which a black or one-channel surface still receives.
bool giHasDiffuseLobe(MaterialSample m) { return (m.flags & MATERIAL_FLAG_GLOSSY) == 0u || m.metallic < 1.0; }

// World-space triangle corners of (instance, geometry, triangle).
void giTriangleWorld(uint instance, uvec3 tri, out vec3 p0, out vec3 p1, out vec3 p2) {
  mat4 m = sceneInstance(instance).worldFromObject;
  p0 = (m * vec4(scenePosition(tri.x), 1.0)).xyz;
  p1 = (m * vec4(scenePosition(tri.y), 1.0)).xyz;
  p2 = (m * vec4(scenePosition(tri.z), 1.0)).xyz;
}

// Interpolated world normal (unit) and the triangle normal oriented to agree with it.
void giTriangleNormals(uint instance, uvec3 tri, vec3 w, vec3 p0, vec3 p1, vec3 p2, out vec3 shading, out vec3 geometric) {
  mat3 nm = mat3(sceneInstance(instance).normalWorldFromObject);
  vec3 n = nm * (sceneNormal(tri.x) * w.x + sceneNormal(tri.y) * w.y + sceneNormal(tri.z) * w.z);
  float nl = length(n);
  vec3 g = cross(p1 - p0, p2 - p0);
  float gl = length(g);
  geometric = gl > 0.0 ? g / gl : (nl > 0.0 ? n / nl : vec3(0.0, 1.0, 0.0));
  shading = nl > 0.0 ? n / nl : geometric;
  if (dot(geometric, shading) < 0.0) geometric = -geometric;
}

GiSurface giSurfaceFromHit(GiHit hit, vec3 rayDirection) {
  GiSurface s;
  uvec3 tri = sceneTriangle(hit.geometry, hit.triangle);
  vec3 w = giBarycentricWeights(hit.barycentrics);
  vec3 p0, p1, p2;
  giTriangleWorld(hit.instance, tri, p0, p1, p2);
  s.position = p0 * w.x + p1 * w.y + p2 * w.z;
  giTriangleNormals(hit.instance, tri, w, p0, p1, p2, s.normal, s.geometricNormal);
  s.frontFace = dot(s.geometricNormal, rayDirection) < 0.0;
  if (!s.frontFace) {
    s.normal = -s.normal;
    s.geometricNormal = -s.geometricNormal;
  }
  // Interpolated normals can face away from the viewer near silhouettes; fall back to the true normal.
  if (dot(s.normal, rayDirection) > 0.0) s.normal = s.geometricNormal;
  s.uv = sceneUv(tri, w);
  s.material = sceneMaterial(sceneGeometry(hit.geometry).material, s.uv);
  if (!s.frontFace) s.material.emission = vec3(0.0);
  return s;
}

#endif
