// Next-event estimation: every punctual light (delta lights, no MIS), or
// with LIGHT_SAMPLER_POWER one of them picked by its power, or with
// LIGHT_SAMPLER_TREE every directional light and one point or spot light
// from each subtree of the light tree's cut; and one shadow ray towards the area lights: an emissive
// triangle (picked by power, or with LIGHT_SAMPLER_TREE down the emissive triangles' tree) or the sky
// (sky.glsl), each with MIS against BSDF sampling. Where a scene has
// both, one of them is picked (giSkySelection: 1/2, or the sky's share of
// the importance beside the triangles' tree; one-sample MIS between them),
// so NEE traces one traversal for them, not two.
// NEE is a ray machine (GiNee): it hands out its shadow rays one at a time,
// so the program that runs it traces them through its one giTrace call
// (trace.glsl says why).
// Specialisation constants (scene.glsl) drop the loops a scene does not need.
#ifndef GI_LIGHTS_GLSL
#define GI_LIGHTS_GLSL
#include "bsdf.glsl"
#include "random.glsl"
#include "surface.glsl"

// A shadow ray of next-event estimation and the light it brings if nothing blocks it.
struct GiShadowRay {
  vec3 origin;
  vec3 direction;
  float tMax;
  vec3 contribution;  // f·Le·(MIS weight)/(selection × light pdf)
};

#include "sky.glsl"

// NEE's light sampler (LIGHT_SAMPLER_*): every program that runs NEE defines it, the module's from its
// frame constants (gi::LightSettings, gi_frame.glsl), the reference path tracer the scene's.
uint giLightSampler();
// What a primary hit's reservoir (gi_reservoirs.comp) stands for, where NEE is handed one: the point and
// spot lights, the emissive triangles, or both, and with either the sky where it has a map
// (GiFrameConstants::primaryDirect; giReservoirsSampleSky); the others are NEE's own. The reference path
// tracer has no reservoirs.
bool giReservoirsHoldPunctual();
bool giReservoirsHoldEmissive();
bool giReservoirsHoldSky();
// Where they hold the sky, the share of recent sky picks whose shadow ray saw it (GiFrameConstants::
// skyVisibility; 1 in the reference path tracer).
float giReservoirsSkyVisibility();


uint giPickEmissiveTriangle(float u) {
  uint lo = 0u, hi = sceneConstants().emissiveTriangleCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (sceneEmissiveTriangle(mid).cdf <= u) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}

// The chance giPickEmissiveTriangle picks entry k: its share of the cdf. Not luminance over the total
// power: a mesh deformed through device streams keeps the cdf of its areas when the table was built, and
// the picks stay unbiased with the pdf this chance over the triangle's area now (giTriangleArea).
float giEmissiveTriangleChance(uint k) {
  return sceneEmissiveTriangle(k).cdf - (k > 0u ? sceneEmissiveTriangle(k - 1u).cdf : 0.0);
}

// The emissive triangles' entry of (instance, geometry, triangle): their table is in that order. An
// emitter's own entry; 0xffffffff for a triangle the table does not hold.
uint giFindEmissive(uint instance, uint geometry, uint triangle) {
  uint lo = 0u, hi = sceneConstants().emissiveTriangleCount - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) / 2u;
    const GpuEmissiveTriangle e = sceneEmissiveTriangle(mid);
    const bool before = e.instance < instance ||
                        (e.instance == instance && (e.geometry < geometry || (e.geometry == geometry && e.triangle < triangle)));
    if (before) lo = mid + 1u;
    else hi = mid;
  }
  const GpuEmissiveTriangle e = sceneEmissiveTriangle(lo);
  return e.instance == instance && e.geometry == geometry && e.triangle == triangle ? lo : 0xffffffffu;
}

// The world area of an emissive triangle's vertices (m²).
float giTriangleArea(vec3 p0, vec3 p1, vec3 p2) { return 0.5 * length(cross(p1 - p0, p2 - p0)); }

// Whether NEE picks emissive triangles down their tree (else by power): LIGHT_SAMPLER_TREE with more of
// them than LIGHT_EMISSIVE_TREE_MIN.
bool giEmissiveTree() {
  return giLightSampler() == LIGHT_SAMPLER_TREE && sceneConstants().emissiveTriangleCount > LIGHT_EMISSIVE_TREE_MIN;
}

// A node of the point and spot lights' tree, or of the emissive triangles'.
GpuLightNode giTreeNode(bool emissive, uint index) { return emissive ? sceneEmissiveNode(index) : sceneLightNode(index); }

// LIGHT_SAMPLER_TREE: a leaf picked from node `index` down, each child with its share of the two
// children's importance (lightNodeImportance, shared/light_tree.h) at x (geometric normal ng), and the
// chance of that pick within the node (0: none of its emitters can light the surface).
uint giPickFromTree(bool emissive, uint index, vec3 x, vec3 ng, float u, out float chance) {
  chance = 1.0;
  // The node the walk stands on is the child it loaded one level up: each level fetches two nodes, not three.
  GpuLightNode n = giTreeNode(emissive, index);
  for (uint depth = 0u; depth < 64u; ++depth) {
    if ((n.child & LIGHT_NODE_LEAF) != 0u) return n.child & ~LIGHT_NODE_LEAF;
    const GpuLightNode left = giTreeNode(emissive, n.child), right = giTreeNode(emissive, n.child + 1u);
    const float a = lightNodeImportance(left, x, ng);
    const float b = lightNodeImportance(right, x, ng);
    if (!(a + b > 0.0)) break;
    const float p = a / (a + b);
    // One random number serves every level: the part of [0, 1) the choice leaves is stretched back to it.
    if (u < p) {
      u /= p;
      chance *= p;
      n = left;
    } else {
      u = (u - p) / (1.0 - p);
      chance *= 1.0 - p;
      n = right;
    }
    u = min(u, 0.99999994);
  }
  chance = 0.0;
  return 0u;
}

// The chance giPickFromTree(emissive, 0, x, ng, ·) picks node `leaf`: its choices walked up from the leaf.
// Each level fetches the parent and the sibling; the node itself is the parent of the level below.
float giTreeLeafChance(bool emissive, uint leaf, vec3 x, vec3 ng) {
  float chance = 1.0;
  uint node = leaf;
  GpuLightNode here = giTreeNode(emissive, leaf);
  for (uint depth = 0u; depth < 64u && node != 0u; ++depth) {
    const uint parent = here.parent;
    const GpuLightNode up = giTreeNode(emissive, parent);
    const bool first = node == up.child;
    const GpuLightNode sibling = giTreeNode(emissive, first ? up.child + 1u : up.child);
    const float mine = lightNodeImportance(here, x, ng), other = lightNodeImportance(sibling, x, ng);
    const float a = first ? mine : other, b = first ? other : mine;
    if (!(a + b > 0.0)) return 0.0;
    const float p = a / (a + b);
    chance *= first ? p : 1.0 - p;
    node = parent;
    here = up;
  }
  return chance;
}

// Emissive triangle k's point at u ∈ [0,1)² (a warp uniform in area) seen from s: the shadow ray towards
// it, with f·Le in ray.contribution (the caller weighs it); L the direction to the point, dist2 its squared
// distance, cosLight the cosine at the emitter and area the triangle's (m²). False when it cannot light s.
bool giEmissivePoint(uint k, vec2 u, GiSurface s, GiBsdf b, vec3 V, out GiShadowRay ray, out vec3 L, out float dist2,
                     out float cosLight, out float area) {
  area = 0.0;
  GpuEmissiveTriangle e = sceneEmissiveTriangle(k);
  uvec3 tri = sceneTriangle(e.geometry, e.triangle);
  float su = sqrt(u.x);
  vec3 w = vec3(1.0 - su, su * (1.0 - u.y), su * u.y);
  vec3 p0, p1, p2, ns, ng;
  giTriangleWorld(e.instance, tri, p0, p1, p2);
  vec3 y = p0 * w.x + p1 * w.y + p2 * w.z;
  giTriangleNormals(e.instance, tri, w, p0, p1, p2, ns, ng);
  vec3 toLight = y - s.position;
  dist2 = dot(toLight, toLight);
  if (!(dist2 > 0.0)) return false;
  float dist = sqrt(dist2);
  L = toLight / dist;
  cosLight = dot(ng, -L);
  if (cosLight <= 0.0) return false;  // emission is one-sided
  vec3 f = giBsdfEval(b, s.normal, V, L);
  if (dot(s.geometricNormal, L) <= 0.0 || giMaxComponent(f) <= 0.0) return false;
  GpuMaterial m = sceneMaterialData(sceneGeometry(e.geometry).material);
  vec3 Le = m.emission;
  if (m.emissiveTexture != NO_TEXTURE) Le *= sceneTexture(m.emissiveTexture, sceneUv(tri, w)).rgb;
  area = giTriangleArea(p0, p1, p2);
  if (!(area > 0.0)) return false;  // deformed to a sliver: it emits nothing
  ray.origin = giOffsetRay(s.position, s.geometricNormal);
  vec3 seg = giOffsetRay(y, -L) - ray.origin;
  ray.tMax = length(seg);
  if (!(ray.tMax > 0.0)) return false;
  ray.direction = seg / ray.tMax;
  ray.contribution = f * Le;
  return true;
}

// The emissive triangle's shadow ray, picked with probability `selection`.
// withMis: weight against BSDF sampling (the caller also adds BSDF-sampled emission).
bool giPrepareEmissive(GiSurface s, GiBsdf b, vec3 V, bool withMis, float selection, inout GiRng rng, out GiShadowRay ray) {
  const bool tree = giEmissiveTree();
  float chance = 1.0;  // the tree's pick's
  const uint k = tree ? giPickFromTree(true, 0u, s.position, s.geometricNormal, giRandom(rng), chance)
                      : giPickEmissiveTriangle(giRandom(rng));
  if (!(chance > 0.0)) return false;  // none of the triangles can light s
  vec3 L;
  float dist2, cosLight, area;
  if (!giEmissivePoint(k, giRandom2(rng), s, b, V, ray, L, dist2, cosLight, area)) return false;
  const float areaPdf = (tree ? chance : giEmissiveTriangleChance(k)) / area;
  float lightPdf = selection * (areaPdf * dist2 / cosLight);
  float mis = withMis ? giPowerHeuristic(lightPdf, giBsdfPdf(b, s.normal, V, L)) : 1.0;
  ray.contribution = ray.contribution * (mis / lightPdf);
  return true;
}

// A reservoir's emissive sample (GI_RESERVOIR_EMISSIVE): the triangle's entry k in the low
// giEmissiveIndexBits() bits, above them the cell of a grid of 2^g × 2^g over the point's u (g =
// giEmissiveGridBits(): the bits the table's size leaves, at most 11, keeping bit 30 clear so that no
// sample reads as GI_RESERVOIR_EMPTY or the other markers). The sample is the cell's centre: the
// reservoirs resample a fixed point of the triangle (from 2^8 to 2^22 of them), which the neighbours and
// the next frame can reuse.
uint giEmissiveIndexBits() { return uint(findMSB(max(sceneConstants().emissiveTriangleCount, 2u) - 1u)) + 1u; }
uint giEmissiveGridBits() { return min((30u - giEmissiveIndexBits()) / 2u, 11u); }
uint giPackEmissiveSample(uint k, vec2 u) {
  const uint g = giEmissiveGridBits(), n = 1u << g;
  const uvec2 cell = min(uvec2(u * float(n)), uvec2(n - 1u));
  return GI_RESERVOIR_EMISSIVE | (((cell.y << g) | cell.x) << giEmissiveIndexBits()) | k;
}
uint giEmissiveSampleTriangle(uint id) { return id & ((1u << giEmissiveIndexBits()) - 1u); }
vec2 giEmissiveSampleUv(uint id) {
  const uint g = giEmissiveGridBits(), cells = (id & ~GI_RESERVOIR_EMISSIVE) >> giEmissiveIndexBits();
  return (vec2(cells & ((1u << g) - 1u), cells >> g) + 0.5) / float(1u << g);
}

// Punctual light i's shadow ray; false when it cannot light s.
bool giPreparePunctual(uint i, GiSurface s, GiBsdf b, vec3 V, out GiShadowRay ray) {
  GpuPunctualLight l = scenePunctualLight(i);
  ray.origin = giOffsetRay(s.position, s.geometricNormal);
  vec3 L;
  float tMax;
  vec3 radiance = l.intensity;  // becomes irradiance at the receiver (W/m²)
  if (l.type == PUNCTUAL_DIRECTIONAL) {
    L = -l.direction;
    tMax = GI_FLT_MAX;
  } else {
    vec3 d = l.position - ray.origin;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0)) return false;
    float dist = sqrt(dist2);
    L = d / dist;
    tMax = dist;
    radiance /= dist2;
    if (l.range > 0.0) {  // KHR_lights_punctual's recommended smooth range window
      float r = dist / l.range;
      radiance *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
    }
    if (l.type == PUNCTUAL_SPOT) {
      float cd = dot(l.direction, -L);
      float scale = 1.0 / max(l.cosInner - l.cosOuter, 1e-4);
      float t = clamp((cd - l.cosOuter) * scale, 0.0, 1.0);
      radiance *= t * t;
    }
  }
  if (dot(s.geometricNormal, L) <= 0.0) return false;
  vec3 f = giBsdfEval(b, s.normal, V, L);
  if (giMaxComponent(f * radiance) <= 0.0) return false;
  ray.direction = L;
  ray.tMax = tMax;
  ray.contribution = f * radiance;
  return true;
}

// How much a tree's lights may bring to x (geometric normal ng): its root's children's importance (the
// root's own bounds every light at once, far looser).
float giTreeImportance(bool emissive, vec3 x, vec3 ng) {
  const GpuLightNode root = giTreeNode(emissive, 0u);
  if ((root.child & LIGHT_NODE_LEAF) != 0u) return lightNodeImportance(root, x, ng);
  return lightNodeImportance(giTreeNode(emissive, root.child), x, ng) +
         lightNodeImportance(giTreeNode(emissive, root.child + 1u), x, ng);
}

// The sky's share beside `others`, the importance of the lights it shares a pick with: its irradiance
// against theirs (1/2 where neither can light the vertex).
float giSkyShare(float others) {
  const float skyImportance = sceneConstants().skyIrradiance;
  const float total = skyImportance + others;
  return total > 0.0 ? skyImportance / total : 0.5;
}

// Probability that the area-light shadow ray from x (geometric normal ng) goes to the sky, where emissive
// triangles (unless a reservoir holds them: `withTriangles` false) and a sampled sky (unless a reservoir holds
// it: `withSky` false) share it: where the triangles are picked down their tree (giEmissiveTree) the sky is
// one more node beside it, chosen by its irradiance against the root's importance at x (all of it where no
// triangle can light x); else 1/2. All or nothing where only one of them is there. With MIS a constant sky
// is not sampled (BSDF sampling finds it), so it takes no share.
float giSkySelection(bool withMis, bool withTriangles, bool withSky, vec3 x, vec3 ng) {
  bool emissive = withTriangles && GI_SCENE_HAS_EMISSIVE && sceneConstants().emissiveTriangleCount > 0u;
  bool sky = withSky && GI_SCENE_HAS_SKY && (giSkyHasMap() || !withMis) && giMaxComponent(sceneConstants().skyRadiance) > 0.0;
  if (!sky) return 0.0;
  if (!emissive) return 1.0;
  if (!giEmissiveTree()) return 0.5;
  return giSkyShare(giTreeImportance(true, x, ng));
}

// Whether a primary hit's reservoir holds the sky: the frame's reservoirs take it and it has a map (a
// constant sky has no light pdf to resample with: BSDF sampling finds it, as at every other vertex).
bool giReservoirsSampleSky() {
  return GI_SCENE_HAS_SKY && giReservoirsHoldSky() && giSkyHasMap() && giMaxComponent(sceneConstants().skyRadiance) > 0.0;
}

// The chance that a reservoir's candidate at x (geometric normal ng) is a sky direction: its irradiance
// against the importance of the lights the reservoirs hold beside it, down their trees (giSkySelection's
// rule), without the trees one equal share per kind of light; either times the sky's measured visibility
// (giReservoirsSkyVisibility: an occluded sky draws few candidates, and BSDF sampling takes its light). 0
// where the reservoirs do not hold the sky.
float giReservoirSkyShare(vec3 x, vec3 ng) {
  if (!giReservoirsSampleSky()) return 0.0;
  const bool punctual = giReservoirsHoldPunctual() && GI_SCENE_HAS_PUNCTUAL;
  const bool emissive = giReservoirsHoldEmissive() && GI_SCENE_HAS_EMISSIVE && sceneConstants().emissiveTriangleCount > 0u;
  if (!punctual && !emissive) return 1.0;
  if (giLightSampler() != LIGHT_SAMPLER_TREE || (emissive && !giEmissiveTree()))
    return (punctual && emissive ? 1.0 / 3.0 : 0.5) * giReservoirsSkyVisibility();
  const float importance = (punctual ? giTreeImportance(false, x, ng) : 0.0) + (emissive ? giTreeImportance(true, x, ng) : 0.0);
  return giSkyShare(importance) * giReservoirsSkyVisibility();
}

// The solid-angle density of a reservoir's sky candidates in direction `dir` at surface `s`: the sky's
// share times the map's density. The reservoirs resample the sky's light weighed by the power heuristic of
// this density against the BSDF's (giPrepareReservoirLight); a BSDF-sampled ray from the primary hit that
// leaves the scene takes the rest (path.glsl), so together they count the sky's light once.
float giReservoirSkyPdf(vec3 dir, GiSurface s) {
  return giReservoirSkyShare(s.position, s.geometricNormal) * giSkyLightPdf(dir);
}

// A reservoir's sky sample: GI_RESERVOIR_SKY and the direction, octahedral, 15 bits a coordinate (about
// 1e-4 rad apart: far finer than any map's texels, over which its density is constant).
uint giPackSkySample(vec3 dir) {
  const uvec2 q = uvec2(round((giOctahedralEncode(dir) * 0.5 + 0.5) * 32767.0));
  return GI_RESERVOIR_SKY | (q.y << 15u) | q.x;
}
bool giIsSkySample(uint id) { return (id & (GI_RESERVOIR_EMISSIVE | GI_RESERVOIR_SKY)) == GI_RESERVOIR_SKY; }
vec3 giSkySampleDirection(uint id) {
  const vec2 e = vec2(uvec2(id, id >> 15u) & 0x7fffu) / 32767.0 * 2.0 - 1.0;
  return normalize(giOctahedralDecode(e));
}
// giReservoirSkyShare for one reservoir's light at s: the share where the light is a sky direction, else 0 (what
// giPrepareReservoirLight takes where it evaluates one light).
float giReservoirSkyShareOf(uint id, GiSurface s) {
  return giIsSkySample(id) ? giReservoirSkyShare(s.position, s.geometricNormal) : 0.0;
}

// A reservoir's light (a punctual light, an emissive triangle's sample point or a sky direction): its shadow
// ray and, in ray.contribution, the light it sends towards V unshadowed, per the measure the reservoirs
// sample it in: f·I/d² for a punctual light, f·L·w per steradian for a sky direction (w its MIS weight),
// f·Le·cos θ_y / d² per unit of emitter area for a triangle's point (`area`: the triangle's, m², which turns
// a pick's chance into the point's density; 0 for the others). False when it cannot light s, or it is not
// one of the lights the reservoirs hold now. `skyShare`: giReservoirSkyShare at s, which a pass evaluating
// many lights at one surface finds once.
bool giPrepareReservoirLight(uint id, GiSurface s, GiBsdf b, vec3 V, float skyShare, out GiShadowRay ray,
                             out float area) {
  const GpuSceneConstants c = sceneConstants();
  area = 0.0;
  if (giIsSkySample(id)) {
    // The sky's light towards V weighed against BSDF sampling (giReservoirSkyPdf says why).
    if (!giReservoirsSampleSky()) return false;
    const vec3 L = giSkySampleDirection(id);
    if (dot(s.geometricNormal, L) <= 0.0) return false;
    const vec3 f = giBsdfEval(b, s.normal, V, L);
    const float w = giPowerHeuristic(skyShare * giSkyLightPdf(L), giBsdfPdf(b, s.normal, V, L));
    ray.origin = giOffsetRay(s.position, s.geometricNormal);
    ray.direction = L;
    ray.tMax = GI_FLT_MAX;
    ray.contribution = f * giSkyRadiance(L) * w;
    return giMaxComponent(ray.contribution) > 0.0;
  }
  if ((id & GI_RESERVOIR_EMISSIVE) == 0u) {
    // Directional lights are NEE's at every vertex; an index past the table is last frame's after
    // gi::updateLights shrank it.
    if (!giReservoirsHoldPunctual() || id < c.directionalLightCount || id >= c.punctualLightCount) return false;
    return giPreparePunctual(id, s, b, V, ray);
  }
  const uint k = giEmissiveSampleTriangle(id);
  if (!GI_SCENE_HAS_EMISSIVE || !giReservoirsHoldEmissive() || k >= c.emissiveTriangleCount) return false;
  vec3 L;
  float dist2, cosLight;
  if (!giEmissivePoint(k, giEmissiveSampleUv(id), s, b, V, ray, L, dist2, cosLight, area)) return false;
  ray.contribution *= cosLight / dist2;
  return true;
}
// The same where the caller needs no area and evaluates one light at s (the shading turn).
bool giPrepareReservoirLight(uint id, GiSurface s, GiBsdf b, vec3 V, out GiShadowRay ray) {
  float area;
  return giPrepareReservoirLight(id, s, b, V, giReservoirSkyShareOf(id, s), ray, area);
}

// Solid-angle densities with which NEE (with MIS) picks an emitter's point or
// a sky direction, for BSDF-sampled hits to weigh themselves against: the emissive point `s` of `hit`
// (s.frontFace holds) seen from `origin`, the ray's origin off the surface `from` (the NEE there picked
// its triangle at from.position, facing from.geometricNormal; `withSky` false where a reservoir holds the
// sky there, which then takes no share of that NEE's ray).
float giEmissiveNeePdf(GiSurface s, GiHit hit, vec3 origin, GiSurface from, bool withSky) {
  if (!GI_SCENE_HAS_EMISSIVE || sceneConstants().emissiveTriangleCount == 0u) return 0.0;
  vec3 d = s.position - origin;
  float dist2 = dot(d, d);
  float cosLight = abs(dot(s.geometricNormal, normalize(d)));
  const uint k = giFindEmissive(hit.instance, hit.geometry, hit.triangle);
  if (k == 0xffffffffu) return 0.0;
  vec3 p0, p1, p2;
  giTriangleWorld(hit.instance, sceneTriangle(hit.geometry, hit.triangle), p0, p1, p2);
  const float chance = giEmissiveTree() ? giTreeLeafChance(true, sceneEmissiveLeaf(k), from.position, from.geometricNormal)
                                        : giEmissiveTriangleChance(k);
  const float area = giTriangleArea(p0, p1, p2);
  if (!(area > 0.0)) return 0.0;
  const float areaPdf = chance / area;
  return (1.0 - giSkySelection(true, true, withSky, from.position, from.geometricNormal)) * areaPdf * dist2 /
         max(cosLight, 1e-8);
}
float giSkyNeePdf(vec3 dir, GiSurface from, bool triangles) {
  return giSkySelection(true, triangles, true, from.position, from.geometricNormal) * giSkyLightPdf(dir);
}

// The area lights' one shadow ray (giSkySelection shares it between the sky
// and the emissive triangles, unless a reservoir holds those: `triangles` false, or the sky: `sky` false);
// false when there is none or it cannot light s.
bool giPrepareArea(GiSurface s, GiBsdf b, vec3 V, bool withMis, bool triangles, bool sky, inout GiRng rng,
                   out GiShadowRay ray) {
  bool emissive = triangles && GI_SCENE_HAS_EMISSIVE && sceneConstants().emissiveTriangleCount > 0u;
  float skyChance = giSkySelection(withMis, triangles, sky, s.position, s.geometricNormal);
  if (!emissive && !(skyChance > 0.0)) return false;
  // Scenes without a sky draw no extra random number: their paths are as before.
  bool pickSky = skyChance >= 1.0 || (skyChance > 0.0 && giRandom(rng) < skyChance);
  return pickSky ? giPrepareSky(s, b, V, withMis, skyChance, rng, ray)
                 : giPrepareEmissive(s, b, V, withMis, 1.0 - skyChance, rng, ray);
}

// LIGHT_SAMPLER_POWER: the punctual light whose share of the power holds u, and that share (> 0).
uint giPickPunctual(float u, out float chance) {
  uint lo = 0u, hi = sceneConstants().punctualLightCount - 1u;
  while (lo < hi) {
    const uint mid = (lo + hi) / 2u;
    if (scenePunctualLightCdf(mid) <= u) lo = mid + 1u;
    else hi = mid;
  }
  chance = scenePunctualLightCdf(lo) - (lo > 0u ? scenePunctualLightCdf(lo - 1u) : 0.0);
  return lo;
}

// The turns NEE takes for the punctual lights: one a light (all); one in all when a light picked by power
// stands for them (power); one a directional light and one a subtree of the cut (tree); with a reservoir
// that holds them, one a directional light. A picked light brings its light over its chance of being
// picked. With a reservoir, one more, the last, for the reservoir's light.
uint giNeePunctualTurns(uvec2 reservoir) {
  const uint reservoirTurn = giUsesReservoir(reservoir) ? 1u : 0u;
  if (!GI_SCENE_HAS_PUNCTUAL) return reservoirTurn;
  const GpuSceneConstants c = sceneConstants();
  if (reservoirTurn > 0u && giReservoirsHoldPunctual()) return c.directionalLightCount + 1u;
  if (giLightSampler() == LIGHT_SAMPLER_POWER) return min(c.punctualLightCount, 1u) + reservoirTurn;
  if (giLightSampler() == LIGHT_SAMPLER_TREE) return c.directionalLightCount + c.lightCutSize + reservoirTurn;
  return c.punctualLightCount + reservoirTurn;
}

// Next-event estimation at one surface as a ray machine: giNeeNextRay tries
// the lights one at a time (each punctual light or the one picked, then the
// area-light sample), giNeeTakeHit takes each shadow ray's answer. Once
// giNeeComplete, `light` is the reflected direct light towards V: f·cos·L / pdf
// summed over them.
struct GiNee {
  uint next;     // the next turn: punctual lights (giNeePunctualTurns), then the area lights; done past them
  vec3 light;    // what the unblocked shadow rays brought so far
  vec3 pending;  // what the ray handed out last brings if unblocked
  uvec2 reservoir;  // the request's (GiNeeRequest::reservoir)
};

// With GI_NO_NEE the estimate is complete before its first turn: no light, no ray.
GiNee giNeeStart(uvec2 reservoir) {
  return GiNee(reservoir == GI_NO_NEE ? 0xffffffffu : 0u, vec3(0.0), vec3(0.0), reservoir);
}

// Tries the next light (each call one: lanes of a subgroup that run NEE
// together stay at the same turn, so each call prepares a punctual light or
// the area lights, not both under a mask). True with its shadow ray; false
// when that light cannot light s, or when every light has been tried
// (giNeeComplete). withMis as in giPrepareEmissive.
bool giNeeNextRay(inout GiNee nee, GiSurface s, GiBsdf b, vec3 V, bool withMis, inout GiRng rng, out GiRay ray) {
  const uint turns = giNeePunctualTurns(nee.reservoir);
  if (nee.next > turns) return false;
  const uint i = nee.next++;
  GiShadowRay shadow;
  bool ready;
  const uint lightSampler = giLightSampler();
  if (i + 1u == turns && giUsesReservoir(nee.reservoir)) {
    // The reservoir's light, weighed by its W: its shadow ray was traced by the reservoir pass (W = 0
    // where it is occluded), so it brings its light without one.
    const float W = uintBitsToFloat(nee.reservoir.y);
    if (nee.reservoir.x != GI_RESERVOIR_EMPTY && W > 0.0 && giPrepareReservoirLight(nee.reservoir.x, s, b, V, shadow))
      nee.light += shadow.contribution * W;
    return false;
  } else if (i < turns && lightSampler == LIGHT_SAMPLER_POWER) {
    float chance;
    ready = giPreparePunctual(giPickPunctual(giRandom(rng), chance), s, b, V, shadow);
    shadow.contribution /= chance;
  } else if (i < turns && lightSampler == LIGHT_SAMPLER_TREE && i >= sceneConstants().directionalLightCount) {
    // A subtree of one light is that light (no random number: with no more lights than the cut has
    // subtrees, the tree traces what `all` does).
    const uint node = sceneLightCutNode(i - sceneConstants().directionalLightCount);
    const uint leaf = sceneLightNode(node).child;
    float chance = 1.0;
    const uint light = (leaf & LIGHT_NODE_LEAF) != 0u ? leaf & ~LIGHT_NODE_LEAF
                                                      : giPickFromTree(false, node, s.position, s.geometricNormal, giRandom(rng), chance);
    ready = chance > 0.0 && giPreparePunctual(light, s, b, V, shadow);
    shadow.contribution /= max(chance, 1e-30);
  } else if (i < turns) {
    ready = giPreparePunctual(i, s, b, V, shadow);
  } else {
    const bool reservoir = giUsesReservoir(nee.reservoir);
    ready = giPrepareArea(s, b, V, withMis, !(reservoir && giReservoirsHoldEmissive()),
                          !(reservoir && giReservoirsSampleSky()), rng, shadow);
  }
  if (!ready) return false;
  nee.pending = shadow.contribution;
  ray = giShadowRay(shadow.origin, shadow.direction, shadow.tMax);
  return true;
}

// True once every light has been tried: no further ray would come.
bool giNeeComplete(GiNee nee) { return nee.next > giNeePunctualTurns(nee.reservoir); }

void giNeeTakeHit(inout GiNee nee, GiHit hit) {
  if (hit.t < 0.0) nee.light += nee.pending;
}

// What a ray task (ray_loop.glsl) asks of the ray loop at each step.
#define GI_STEP_DONE 0u   // the task is finished
#define GI_STEP_TRACE 1u  // trace the ray it gave; the hit comes back through giTaskTakeHit
#define GI_STEP_NEE 2u    // run NEE as it asked; the light comes back through giTaskTakeNee
#define GI_STEP_WAIT 3u   // nothing this turn: the lane waits for the subgroup to come into step

// NEE as a task asks for it: at s (BSDF b) towards V, with the task's random
// state, which NEE advances and hands back with the light.
struct GiNeeRequest {
  GiSurface s;
  GiBsdf b;
  vec3 V;
  bool withMis;
  GiRng rng;
  uvec2 reservoir;  // a primary hit's reservoir, or GI_NO_RESERVOIR
};

#endif
