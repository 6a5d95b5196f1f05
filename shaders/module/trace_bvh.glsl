// The compute traversal backend of trace.glsl (compiled with GI_TRACE_COMPUTE):
// our two-level 4-wide BVH (shared/gpu_bvh.h), walked with one short stack.
// Hits report the same ids as ray queries (instance, absolute geometry,
// triangle, barycentrics of v1 and v2); alpha-masked geometry is tested
// against its texture as ray queries' candidate loop does.
#ifndef GI_TRACE_BVH_GLSL
#define GI_TRACE_BVH_GLSL

// The structs of shared/gpu_bvh.h from their texel buffers (16-byte rows,
// fetched as integers so ids and float bits pass unchanged).
GpuBvhNode giBvhNodeFrom(utextureBuffer nodes, uint index) {
  int base = int(index * 7u);
  GpuBvhNode n;
  n.minX = uintBitsToFloat(GI_FETCH(nodes, base));
  n.minY = uintBitsToFloat(GI_FETCH(nodes, base + 1));
  n.minZ = uintBitsToFloat(GI_FETCH(nodes, base + 2));
  n.maxX = uintBitsToFloat(GI_FETCH(nodes, base + 3));
  n.maxY = uintBitsToFloat(GI_FETCH(nodes, base + 4));
  n.maxZ = uintBitsToFloat(GI_FETCH(nodes, base + 5));
  n.child = GI_FETCH(nodes, base + 6);
  return n;
}

GpuBvhNode giBvhNode(bool bottom, uint index) {
  return bottom ? giBvhNodeFrom(sceneBvhNodes, index) : giBvhNodeFrom(sceneBvhTopNodes, index);
}

GpuBvhTriangle giBvhTriangle(uint index) {
  int base = int(index * 3u);
  uvec4 a = GI_FETCH(sceneBvhTriangles, base), b = GI_FETCH(sceneBvhTriangles, base + 1),
        c = GI_FETCH(sceneBvhTriangles, base + 2);
  GpuBvhTriangle t;
  t.v0 = uintBitsToFloat(a.xyz);
  t.geometry = a.w;
  t.edge1 = uintBitsToFloat(b.xyz);
  t.triangle = b.w;
  t.edge2 = uintBitsToFloat(c.xyz);
  t.instance = c.w;
  return t;
}

GpuBvhInstance giBvhInstance(uint index) {
  int base = int(index * 4u);
  GpuBvhInstance i;
  i.objectFromWorld0 = uintBitsToFloat(GI_FETCH(sceneBvhInstances, base));
  i.objectFromWorld1 = uintBitsToFloat(GI_FETCH(sceneBvhInstances, base + 1));
  i.objectFromWorld2 = uintBitsToFloat(GI_FETCH(sceneBvhInstances, base + 2));
  uvec4 ids = GI_FETCH(sceneBvhInstances, base + 3);
  i.root = ids.x;
  i.instance = ids.y;
  i.pad0 = 0u;
  i.pad1 = 0u;
  return i;
}

// 1/d without infinities: a zero component becomes ±1e30, so 0 · (1/d) stays 0.
vec3 giBvhSafeInverse(vec3 d) {
  const float tiny = 1e-30;
  return 1.0 / vec3(abs(d.x) < tiny ? (d.x < 0.0 ? -tiny : tiny) : d.x,
                    abs(d.y) < tiny ? (d.y < 0.0 ? -tiny : tiny) : d.y,
                    abs(d.z) < tiny ? (d.z < 0.0 ? -tiny : tiny) : d.z);
}

// Möller–Trumbore, two-sided (ray queries cull nothing either). Degenerate
// triangles (det = 0) are never hit.
bool giBvhTriangleHit(GpuBvhTriangle tri, vec3 origin, vec3 direction, float tMin, float tMax, out float t,
                      out vec2 bary) {
  t = 0.0;
  bary = vec2(0.0);
  vec3 p = cross(direction, tri.edge2);
  float det = dot(tri.edge1, p);
  if (det == 0.0) return false;
  float invDet = 1.0 / det;
  vec3 s = origin - tri.v0;
  float u = dot(s, p) * invDet;
  if (u < 0.0 || u > 1.0) return false;
  vec3 q = cross(s, tri.edge1);
  float v = dot(direction, q) * invDet;
  if (v < 0.0 || u + v > 1.0) return false;
  t = dot(tri.edge2, q) * invDet;
  if (!(t >= tMin && t <= tMax)) return false;
  bary = vec2(u, v);
  return true;
}

bool giBvhTriangleAccepted(GpuBvhTriangle tri, vec2 bary) {
  if (!GI_SCENE_HAS_ALPHA_MASK) return true;
  if ((sceneMaterialData(sceneGeometry(tri.geometry).material).flags & MATERIAL_FLAG_ALPHA_MASK) == 0u) return true;
  return giAlphaAccepts(tri.geometry, tri.triangle, bary);
}

// Puts lanes a and b of (t, c) in ascending order of t.
#define GI_BVH_ORDER(t, c, a, b)       \
  if (t.b < t.a) {                     \
    float tSwap = t.a;                 \
    t.a = t.b;                         \
    t.b = tSwap;                       \
    uint cSwap = c.a;                  \
    c.a = c.b;                         \
    c.b = cSwap;                       \
  }

// Walks both levels in one loop, so each call site inlines one traversal
// ("while-while": descend inner nodes to a leaf, keeping the nearest child
// and stacking the others; test the leaf; pop). A top-level leaf is one
// instance: the ray moves into its object space (the same t: the direction
// is transformed, not renormalised) and a marker on the stack brings it back.
GiHit giBvhTrace(vec3 origin, vec3 direction, float tMin, float tMax, bool anyHit) {
  GiHit hit = giNoHit();
  float best = tMax;
  vec3 o = origin, d = direction;
  vec3 invDir = giBvhSafeInverse(direction);
  bool bottom = false;  // walking an instance's bottom level
  uint instance = 0u;
  uint stack[BVH_STACK_SIZE];
  float enter[BVH_STACK_SIZE];
  uint sp = 0u;
  uint ref = 0u;  // the top level's root node
  while (true) {
    while (ref != BVH_NO_CHILD && (ref & BVH_LEAF_BIT) == 0u) {
      GpuBvhNode node = giBvhNode(bottom, ref);
      // Four slab tests at once; a missed or empty child gets GI_FLT_MAX.
      vec4 t0x = (node.minX - o.x) * invDir.x, t1x = (node.maxX - o.x) * invDir.x;
      vec4 t0y = (node.minY - o.y) * invDir.y, t1y = (node.maxY - o.y) * invDir.y;
      vec4 t0z = (node.minZ - o.z) * invDir.z, t1z = (node.maxZ - o.z) * invDir.z;
      vec4 near = max(max(min(t0x, t1x), min(t0y, t1y)), max(min(t0z, t1z), vec4(tMin)));
      vec4 far = min(min(max(t0x, t1x), max(t0y, t1y)), min(max(t0z, t1z), vec4(best)));
      bvec4 entered = bvec4(uvec4(lessThanEqual(near, far)) & uvec4(notEqual(node.child, uvec4(BVH_NO_CHILD))));
      vec4 t = mix(vec4(GI_FLT_MAX), near, entered);
      uvec4 c = node.child;
      // Sort the four by entry distance (a five-exchange network), nearest first.
      GI_BVH_ORDER(t, c, x, y) GI_BVH_ORDER(t, c, z, w) GI_BVH_ORDER(t, c, x, z) GI_BVH_ORDER(t, c, y, w)
      GI_BVH_ORDER(t, c, y, z)
      // Descend into the nearest; stack the others, farthest first.
      if (t.w < GI_FLT_MAX && sp < BVH_STACK_SIZE) { stack[sp] = c.w; enter[sp] = t.w; sp++; }
      if (t.z < GI_FLT_MAX && sp < BVH_STACK_SIZE) { stack[sp] = c.z; enter[sp] = t.z; sp++; }
      if (t.y < GI_FLT_MAX && sp < BVH_STACK_SIZE) { stack[sp] = c.y; enter[sp] = t.y; sp++; }
      ref = t.x < GI_FLT_MAX ? c.x : BVH_NO_CHILD;
    }
    if (ref != BVH_NO_CHILD) {
      uint first = ref & BVH_LEAF_FIRST_MASK;
      if (!bottom) {  // enter the instance
        GpuBvhInstance inst = giBvhInstance(first);
        vec4 o4 = vec4(origin, 1.0);
        o = vec3(dot(inst.objectFromWorld0, o4), dot(inst.objectFromWorld1, o4), dot(inst.objectFromWorld2, o4));
        d = vec3(dot(inst.objectFromWorld0.xyz, direction), dot(inst.objectFromWorld1.xyz, direction),
                 dot(inst.objectFromWorld2.xyz, direction));
        invDir = giBvhSafeInverse(d);
        instance = inst.instance;
        bottom = true;
        if (sp < BVH_STACK_SIZE) {
          stack[sp] = BVH_LEAVE_INSTANCE;
          enter[sp] = tMin;
          sp++;
        }
        ref = inst.root;
        continue;
      }
      uint count = ((ref >> BVH_LEAF_COUNT_SHIFT) & 15u) + 1u;
      for (uint i = 0u; i < count; ++i) {
        GpuBvhTriangle tri = giBvhTriangle(first + i);
        float t;
        vec2 bary;
        if (!giBvhTriangleHit(tri, o, d, tMin, best, t, bary)) continue;
        if (!giBvhTriangleAccepted(tri, bary)) continue;
        best = t;
        hit.t = t;
        hit.instance = tri.instance != BVH_FROM_TOP_LEVEL ? tri.instance : instance;
        hit.geometry = tri.geometry;
        hit.triangle = tri.triangle;
        hit.barycentrics = bary;
        if (anyHit) return hit;
      }
    }
    // Pop the next subtree the ray still enters before `best`; the marker
    // returns the ray to world space.
    ref = BVH_NO_CHILD;
    while (sp > 0u && ref == BVH_NO_CHILD) {
      sp--;
      if (stack[sp] == BVH_LEAVE_INSTANCE) {
        bottom = false;
        o = origin;
        d = direction;
        invDir = giBvhSafeInverse(direction);
      } else if (enter[sp] <= best) {
        ref = stack[sp];
      }
    }
    if (ref == BVH_NO_CHILD) break;
  }
  return hit;
}

GiHit giTrace(GiRay ray) {
  giRaysTraced++;
  return giBvhTrace(ray.origin, ray.direction, ray.tMin, ray.tMax, ray.anyHit);
}

#endif
