// Set 1 of the GI module's passes (shared/gi_frame.h) and the G-buffer decode:
// the only place that knows how the engine's G-buffer encodes a surface.
#ifndef GI_FRAME_GLSL
#define GI_FRAME_GLSL
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_shader_image_load_formatted : require
#include "bounds.glsl"
#include "common.glsl"
#include "surface.glsl"
#include "camera.glsl"
#include "shared/gi_frame.h"

layout(set = 1, binding = GI_BINDING_FRAME, scalar) uniform GiFrameBlock { GiFrameConstants giFrame; };
layout(set = 1, binding = GI_BINDING_GB_NORMAL) uniform texture2D giGbNormalImage;
layout(set = 1, binding = GI_BINDING_GB_ALBEDO) uniform texture2D giGbAlbedoImage;
layout(set = 1, binding = GI_BINDING_GB_MATERIAL) uniform texture2D giGbMaterialImage;
layout(set = 1, binding = GI_BINDING_GB_EMISSION) uniform texture2D giGbEmissionImage;
layout(set = 1, binding = GI_BINDING_GB_MOTION) uniform texture2D giGbMotionImage;
layout(set = 1, binding = GI_BINDING_GB_DEPTH) uniform texture2D giGbDepthImage;
layout(constant_id = GI_SPEC_NORMAL_ENCODING) const uint GI_NORMAL_ENCODING = GI_NORMAL_XYZ;
layout(constant_id = GI_SPEC_DEPTH_ENCODING) const uint GI_DEPTH_ENCODING = GI_DEPTH_LINEAR_VIEW_Z;
layout(constant_id = GI_SPEC_GLOSSY_FLAG) const uint GI_GLOSSY_FLAG = GI_GLOSSY_ALBEDO_ALPHA;
layout(constant_id = GI_SPEC_HAS_EMISSION) const bool GI_GB_HAS_EMISSION = true;
// Formatless: ModuleDesc::outputFormat picks half or single floats.
layout(set = 1, binding = GI_BINDING_OUT_DIRECT) uniform image2D giOutDirect;
layout(set = 1, binding = GI_BINDING_OUT_INDIRECT) uniform image2D giOutIndirect;
layout(set = 1, binding = GI_BINDING_OUT_COMPOSITE) uniform image2D giOutComposite;
// The engine's packed direct and indirect outputs (B10G11R11), which only the composite pass writes.
layout(set = 1, binding = GI_BINDING_PACKED_DIRECT) uniform writeonly image2D giPackedDirect;
layout(set = 1, binding = GI_BINDING_PACKED_INDIRECT) uniform writeonly image2D giPackedIndirect;
// The radiance histories are half or single floats (GiFrameConstants::historyScale): no format qualifier.
layout(set = 1, binding = GI_BINDING_HISTORY_DIRECT_A) uniform image2D giHistoryDirectA;
layout(set = 1, binding = GI_BINDING_HISTORY_INDIRECT_A) uniform image2D giHistoryIndirectA;
layout(set = 1, binding = GI_BINDING_COUNTERS, scalar) buffer GiCountersBlock { GiCounters giCounters; };
layout(set = 1, binding = GI_BINDING_NOISY_INDIRECT) uniform image2D giNoisyIndirect;  // formatless: may alias an output
layout(set = 1, binding = GI_BINDING_GUIDANCE, rgba16f) uniform image2D giGuidance;
layout(set = 1, binding = GI_BINDING_POSITION, rgba16f) uniform image2D giPosition;
layout(set = 1, binding = GI_BINDING_DEBUG) uniform image2D giDebug;  // formatless: half floats as à-trous's and AAF's temporary
layout(set = 1, binding = GI_BINDING_AAF_PARAMS, rgba16f) uniform image2D giAafParams;
layout(set = 1, binding = GI_BINDING_AAF_GLOSSY, rgba32f) uniform image2D giAafGlossy;
layout(set = 1, binding = GI_BINDING_AAF_GLOSSY_EDGE, rgba32f) uniform image2D giAafGlossyEdge;
layout(set = 1, binding = GI_BINDING_HISTORY_DIRECT_B) uniform image2D giHistoryDirectB;
layout(set = 1, binding = GI_BINDING_HISTORY_INDIRECT_B) uniform image2D giHistoryIndirectB;
layout(set = 1, binding = GI_BINDING_HISTORY_GUIDE, r32ui) uniform uimage2D giHistoryGuide;  // temporal.glsl's giPackGuide
// svgf's variances and history frames (giPackSvgfState): r32ui or rgba32ui, so no format qualifier.
layout(set = 1, binding = GI_BINDING_SVGF_STATE_A) uniform uimage2D giSvgfStateA;
layout(set = 1, binding = GI_BINDING_SVGF_STATE_B) uniform uimage2D giSvgfStateB;
layout(set = 1, binding = GI_BINDING_GRADIENT_SAMPLES_A, rgba32ui) uniform uimage2D giGradientSamplesA;
layout(set = 1, binding = GI_BINDING_GRADIENT_SAMPLES_B, rgba32ui) uniform uimage2D giGradientSamplesB;
layout(set = 1, binding = GI_BINDING_TEMPORAL_GRADIENT, rgba32f) uniform image2D giTemporalGradient;
layout(set = 1, binding = GI_BINDING_TEMPORAL_SPREAD, rgba32f) uniform image2D giTemporalSpread;
layout(set = 1, binding = GI_BINDING_HISTORY_PACKED, rg32ui) uniform uimage2D giHistoryPacked;
layout(set = 1, binding = GI_BINDING_RESERVOIRS_A, rgba32ui) uniform uimage2D giReservoirsA;
layout(set = 1, binding = GI_BINDING_RESERVOIRS_B, rgba32ui) uniform uimage2D giReservoirsB;
layout(set = 1, binding = GI_BINDING_FRAME_RESERVOIRS, rg32ui) uniform uimage2D giFrameReservoirs;
layout(set = 1, binding = GI_BINDING_RESERVOIR_PICK, rg32ui) uniform uimage2D giReservoirPick;

// With ModuleDesc::checkBounds a coordinate outside its image, or an index outside one of the scene's
// texel buffers, is counted here (bounds.glsl).
GI_COUNT_PIXELS_OUTSIDE_INTO(giCounters.boundsViolations)
GI_COUNT_TEXELS_OUTSIDE_INTO(giCounters.boundsViolations)

uint giLightSampler() { return giFrame.lightSampler; }
bool giReservoirsHoldPunctual() { return (giFrame.primaryDirect & GI_PRIMARY_DIRECT_RESERVOIRS) != 0u; }
bool giReservoirsHoldEmissive() { return (giFrame.primaryDirect & GI_PRIMARY_DIRECT_EMISSIVE) != 0u; }
bool giReservoirsHoldSky() { return (giFrame.primaryDirect & GI_PRIMARY_DIRECT_SKY) != 0u; }
float giReservoirsSkyVisibility() { return giFrame.skyVisibility; }
// The frame's primary hits take their reservoir's light (gi_reservoirs.comp).
bool giFrameHasReservoirs() { return giReservoirsHoldPunctual() || giReservoirsHoldEmissive(); }

// The pixel's reservoir for its primary hit's NEE (reservoirs.glsl), GI_NO_RESERVOIR when the frame has none,
// or GI_NO_NEE when the engine lights the primary hits.
uvec2 giPrimaryReservoir(ivec2 p) {
  if (giFrame.primaryDirect == GI_PRIMARY_DIRECT_NONE) return GI_NO_NEE;
  return giFrameHasReservoirs() ? imageLoad(giReservoirPick, p).xy : GI_NO_RESERVOIR;
}

// Output images hold radiance × outputScale, clamped into the format's range
// (a half float overflows to Inf past 65504). Loads give radiance back.
vec3 giOutputEncode(vec3 radiance, float scale, float limit) { return clamp(radiance * scale, vec3(-limit), vec3(limit)); }
#define GI_OUTPUT_ACCESS(Name, image, limit)                                                                    \
  void giStore##Name(ivec2 p, vec3 radiance) { imageStore(image, p, vec4(giOutputEncode(radiance, giFrame.outputScale, limit), 1.0)); } \
  vec3 giLoad##Name(ivec2 p) { return imageLoad(image, p).rgb / giFrame.outputScale; }
GI_OUTPUT_ACCESS(Direct, giOutDirect, giFrame.outputMax)
// The hash methods' temporal pass hands the history's frames to the composite pass in the direct
// output's alpha; the composite puts the 1 back.
void giStoreDirectAndFrames(ivec2 p, vec3 radiance, float frames) {
  imageStore(giOutDirect, p, vec4(giOutputEncode(radiance, giFrame.outputScale, giFrame.outputMax), frames));
}
GI_OUTPUT_ACCESS(Indirect, giOutIndirect, giFrame.outputMax)
GI_OUTPUT_ACCESS(Composite, giOutComposite, giFrame.compositeMax)
// The noisy indirect keeps its alpha (the filter-vertex flag).
void giStoreNoisy(ivec2 p, vec3 radiance, float alpha) {
  imageStore(giNoisyIndirect, p, vec4(giOutputEncode(radiance, giFrame.noisyScale, giFrame.noisyMax), alpha));
}
// With its alpha as stored (AAF's pass 1 keeps its sample count there: aaf.glsl's aafStorePartial).
vec4 giLoadNoisyAndAlpha(ivec2 p) {
  const vec4 v = imageLoad(giNoisyIndirect, p);
  return vec4(v.rgb / giFrame.noisyScale, v.a);
}
vec3 giLoadNoisy(ivec2 p) { return giLoadNoisyAndAlpha(p).rgb; }

// The radiance histories hold radiance × historyScale, clamped to their format's range; their alpha
// (the direct history's frames) as is. Loads give radiance back.
#define GI_HISTORY_ACCESS(Name, image)                                                                   \
  void giStore##Name(ivec2 p, vec3 radiance, float alpha) {                                              \
    imageStore(image, p, vec4(giOutputEncode(radiance, giFrame.historyScale, giFrame.historyMax), alpha)); \
  }                                                                                                      \
  vec4 giLoad##Name(ivec2 p) {                                                                           \
    const vec4 v = imageLoad(image, p);                                                                  \
    return vec4(v.rgb / giFrame.historyScale, v.a);                                                      \
  }
GI_HISTORY_ACCESS(HistoryDirectA, giHistoryDirectA)
GI_HISTORY_ACCESS(HistoryIndirectA, giHistoryIndirectA)
GI_HISTORY_ACCESS(HistoryDirectB, giHistoryDirectB)
GI_HISTORY_ACCESS(HistoryIndirectB, giHistoryIndirectB)
// The indirect history of a set (0 = A, 1 = B).
vec4 giLoadHistoryIndirect(uint set, ivec2 p) {
  return set == 0u ? giLoadHistoryIndirectA(p) : giLoadHistoryIndirectB(p);
}

// svgf's luminance moments of direct (x) and indirect (y) light: their mean and their variance about
// it, not the mean square, in the histories' units (× historyScale, variance × historyScale²); a mean
// square minus a squared mean would cancel to nothing where the variance is small. Each set keeps the
// means in its radiance histories' alphas (the direct history's and the indirect's, in the histories'
// format), and in its state image the two variances and the history's frames, which the other methods
// keep in the direct history's alpha. With half-float histories the state is one word a pixel
// (giPackSvgfState); with single-float ones, single floats (giFrame.svgfWideState). Set 0 = A, 1 = B.
struct GiMoments {
  vec2 mean, variance;
};
// A variance (≥ 0) in 12 bits: its half float without the sign and the 3 lowest mantissa bits, rounded
// (7 mantissa bits: within 0.4% where it is a normal half; the filter's weights take its square root).
// Frames in 8 bits with 2 fractional bits (the history's blend weight is 1 / frames, at least α):
// 0 to 63.75, as the hash methods' frames.
#define GI_SVGF_VARIANCE_MAX 60000.0
uint giPackSvgfVariance(float v) {
  return (packHalf2x16(vec2(clamp(v, 0.0, GI_SVGF_VARIANCE_MAX), 0.0)) + 4u) >> 3u;
}
float giUnpackSvgfVariance(uint bits) { return unpackHalf2x16((bits & 0xfffu) << 3u).x; }
uvec4 giPackSvgfState(vec2 variance, float frames) {
  const vec2 v = variance * giFrame.historyScale * giFrame.historyScale;
  const float f = clamp(frames, 0.0, 63.75);
  if (giFrame.svgfWideState != 0u) return uvec4(floatBitsToUint(v.x), floatBitsToUint(v.y), floatBitsToUint(f), 0u);
  return uvec4(giPackSvgfVariance(v.x) | giPackSvgfVariance(v.y) << 12u | uint(f * 4.0 + 0.5) << 24u, 0u, 0u, 0u);
}
uvec4 giLoadSvgfState(uint set, ivec2 q) { return set == 0u ? imageLoad(giSvgfStateA, q) : imageLoad(giSvgfStateB, q); }
// Whether a pixel's history is GI_TRUSTED_HISTORY frames long. The count is reprojected as a weighted
// mean of its neighbours' counts, which on a GPU with fused multiply-adds (an NVIDIA H200) comes out an
// ulp or two below the count every neighbour holds (3.9999998 for 4): the 1e-3 of slack is far below the
// smallest honest step (1/4, the packed state's) and far above that rounding.
bool giHistoryTrusted(float frames) { return frames >= GI_TRUSTED_HISTORY - 1e-3; }
float giLoadSvgfFrames(uint set, ivec2 q) {
  const uvec4 state = giLoadSvgfState(set, q);
  return giFrame.svgfWideState != 0u ? uintBitsToFloat(state.z) : float(state.x >> 24u) / 4.0;
}
GiMoments giLoadMoments(uint set, ivec2 q) {
  const uvec4 state = giLoadSvgfState(set, q);
  const vec2 variance = giFrame.svgfWideState != 0u
                            ? uintBitsToFloat(state.xy)
                            : vec2(giUnpackSvgfVariance(state.x), giUnpackSvgfVariance(state.x >> 12u));
  const float directMean = (set == 0u ? imageLoad(giHistoryDirectA, q) : imageLoad(giHistoryDirectB, q)).a;
  const float indirectMean = (set == 0u ? imageLoad(giHistoryIndirectA, q) : imageLoad(giHistoryIndirectB, q)).a;
  const float s = giFrame.historyScale;
  return GiMoments(vec2(directMean, indirectMean) / s, variance / (s * s));
}
// The means as the histories' alphas hold them.
vec2 giSvgfMeanAlphas(GiMoments m) {
  return clamp(m.mean * giFrame.historyScale, vec2(0.0), vec2(giFrame.historyMax));
}
void giStoreSvgfState(uint set, ivec2 p, GiMoments m, float frames) {
  const uvec4 v = giPackSvgfState(m.variance, frames);
  if (set == 0u) imageStore(giSvgfStateA, p, v);
  else imageStore(giSvgfStateB, p, v);
}

// --- The G-buffer decode: the only place that knows the engine's encodings.

// The world normal as stored (not normalised: giGbValid checks it).
vec3 giGbNormalRaw(ivec2 p) {
  vec4 v = texelFetch(giGbNormalImage, p, 0);
  if (GI_NORMAL_ENCODING == GI_NORMAL_XYZ_UNORM) return v.xyz * 2.0 - 1.0;
  if (GI_NORMAL_ENCODING == GI_NORMAL_OCTAHEDRAL) return giOctahedralDecode(v.xy * 2.0 - 1.0);
  if (GI_NORMAL_ENCODING == GI_NORMAL_OCTAHEDRAL_SIGNED) return giOctahedralDecode(clamp(v.xy, -1.0, 1.0));
  return v.xyz;
}
vec3 giGbNormal(ivec2 p) { return normalize(giGbNormalRaw(p)); }

// View depth along −Z in metres; 0 for background.
float giGbViewDepth(ivec2 p) {
  float d = texelFetch(giGbDepthImage, p, 0).r;
  if (GI_DEPTH_ENCODING == GI_DEPTH_LINEAR_VIEW_Z) return d;
  if (d == (GI_DEPTH_ENCODING == GI_DEPTH_HARDWARE_REVERSED ? 0.0 : 1.0)) return 0.0;  // the far plane: background
  vec2 ndc = (vec2(p) + 0.5) / vec2(giFrame.size) * 2.0 - 1.0;
  vec4 view = giFrame.viewFromClip * vec4(ndc, d, 1.0);
  return -view.z / view.w;
}

vec4 giGbAlbedo(ivec2 p) { return texelFetch(giGbAlbedoImage, p, 0); }  // linear (an sRGB view decodes)
vec2 giGbRoughnessMetallic(ivec2 p) { return texelFetch(giGbMaterialImage, p, 0).rg; }
// Without an emission view the engine adds emission itself: 0 here (the binding holds another view, unread).
vec3 giGbEmission(ivec2 p) { return GI_GB_HAS_EMISSION ? texelFetch(giGbEmissionImage, p, 0).rgb : vec3(0.0); }
// Direct light is accumulated and filtered over the base colour (SVGF's
// demodulation; gi_temporal.comp, svgf_atrous.comp); darker base colours count
// as 1/64, so black texels keep their light.
vec3 giDirectAlbedo(ivec2 p) { return max(giGbAlbedo(p).rgb, vec3(1.0 / 64.0)); }

// Previous position − current, in pixels, jitter included (gi::GBufferDesc's motion conventions).
vec2 giGbMotionPixels(ivec2 p) {
  return texelFetch(giGbMotionImage, p, 0).rg * giFrame.motionScale + giFrame.motionOffset;
}

// Where pixel p's surface was last frame, in last frame's pixels (continuous, texel centres at +0.5):
// its motion, scaled from this frame's render size to last frame's (dynamic resolution; the motion is in
// this frame's pixels, as the engine rendered it).
vec2 giPreviousPosition(ivec2 p) {
  return (vec2(p) + 0.5 + giGbMotionPixels(p)) * giFrame.previousCamera.imageSize / vec2(giFrame.size);
}
// True for a texel of last frame's render rectangle (the histories hold nothing valid beyond it).
bool giInPreviousFrame(ivec2 q) {
  return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(giFrame.previousCamera.imageSize)));
}

bool giGbGlossy(ivec2 p) {
  if (GI_GLOSSY_FLAG == GI_GLOSSY_FROM_MATERIAL) {
    const vec2 rm = giGbRoughnessMetallic(p);
    return materialHasGlossyLobe(rm.y, rm.x);
  }
  return giGbAlbedo(p).a > 0.5;
}

// True for an invocation inside the frame (the dispatch covers whole groups beyond its edges).
bool giInFrame(uvec2 invocation) { return all(lessThan(invocation, giFrame.size)); }

// True where the G-buffer holds geometry.
bool giGbCoveredRaw(ivec2 p) { return giGbViewDepth(p) != 0.0; }

// Geometry whose G-buffer values are all finite and sane. NaN or Inf coming
// in from the engine stops here: such a pixel is treated as background, so it
// cannot spread through filters, caches or history (counted by the first
// pass through giGbCoveredCounting).
bool giGbValid(ivec2 p) {
  vec3 n = giGbNormalRaw(p);
  float z = giGbViewDepth(p);
  return giIsFinite(n) && dot(n, n) > 1e-12 && !isnan(z) && !isinf(z) && z > 0.0 &&
         giIsFinite(giGbAlbedo(p).rgb) && giIsFinite(giGbEmission(p));
}
bool giGbCovered(ivec2 p) { return giGbCoveredRaw(p) && giGbValid(p); }

uint giSanitizedPixels = 0u;  // this invocation's count, added by giCountRays
bool giGbCoveredCounting(ivec2 p) {
  if (!giGbCoveredRaw(p)) return false;
  if (giGbValid(p)) return true;
  giSanitizedPixels++;
  return false;
}

// World position of pixel p's primary hit from its view depth.
vec3 giGbPosition(ivec2 p, out vec3 dir) {
  dir = giCameraRayDirection(giFrame.camera, vec2(p) + 0.5);
  vec3 forward = -vec3(giFrame.camera.worldFromView[2]);
  float viewZ = giGbViewDepth(p);
  return giFrame.camera.position + dir * (viewZ / max(dot(dir, forward), 1e-6));
}

// The primary hit as a shading point: position from view depth along the
// pixel-centre ray, normal and material from the G-buffer. The G-buffer stores
// no triangle normal, so the (camera-facing) shading normal stands in for it.
// Two errors put the reconstructed point behind the surface, where every ray
// that leaves it is blocked (walls at grazing angles render black):
// - the rasterizer's depth: interpolated, not traced. On an NVIDIA H200 it
//   differed from lavapipe's by up to 2e-4 of the distance (Cornell box at
//   24×24, its walls and floor; scripts/device/diag-depth). The point is pulled back
//   towards the camera by GI_GBUFFER_DEPTH_TOLERANCE of its distance: the
//   view ray is the direction of that error, so the point leaves the surface
//   by tolerance × distance × cos θ, no further than the error at any angle;
// - fp32 camera position + distance (about 2.4e-7 of their size: 6 cm for a
//   camera 1e5 m from the origin): the point is lifted off the surface by four
//   times that, or the rays that leave it (offset for the surface's own
//   coordinates) would hit the surface.
const float GI_GBUFFER_DEPTH_TOLERANCE = 1e-3;  // of the distance from the camera, 5× the error seen
GiSurface giGbSurface(ivec2 p, out vec3 V) {
  GiSurface s;
  vec3 dir;
  s.position = giGbPosition(p, dir);
  s.normal = giGbNormal(p);
  const float distanceFromCamera = distance(giFrame.camera.position, s.position);
  s.position -= dir * (GI_GBUFFER_DEPTH_TOLERANCE * distanceFromCamera);
  float reach = length(giFrame.camera.position) + distanceFromCamera;
  s.position += s.normal * (1e-6 * reach);
  s.geometricNormal = s.normal;
  s.frontFace = true;
  s.uv = vec2(0.0);
  vec2 material = giGbRoughnessMetallic(p);
  s.material.baseColor = giGbAlbedo(p).rgb;
  s.material.alpha = 1.0;
  s.material.roughness = material.r;
  s.material.metallic = material.g;
  s.material.emission = giGbEmission(p);
  s.material.flags = giGbGlossy(p) ? MATERIAL_FLAG_GLOSSY : 0u;
  V = -dir;
  return s;
}

// The albedo that multiplies demodulated indirect light: the diffuse lobe's.
vec3 giGbDiffuseAlbedo(ivec2 p) {
  if (!giGbCovered(p)) return vec3(0.0);
  float metallic = giGbGlossy(p) ? giGbRoughnessMetallic(p).g : 0.0;
  return (1.0 - metallic) * giGbAlbedo(p).rgb;
}

// f0 of the glossy lobe (0 where the pixel has none): multiplies AAF's filtered specular term.
vec3 giGbSpecularF0(ivec2 p) {
  if (!giGbCovered(p)) return vec3(0.0);
  return giGbGlossy(p) ? mix(vec3(0.04), giGbAlbedo(p).rgb, giGbRoughnessMetallic(p).g) : vec3(0.0);
}

void giCountRays(bool counted) {
  uint rays = subgroupAdd(counted ? giRaysTraced : 0u);
  uint sanitized = subgroupAdd(counted ? giSanitizedPixels : 0u);
  if (subgroupElect()) {
    atomicAdd(giCounters.raysTraced, rays);
    if (sanitized > 0u) atomicAdd(giCounters.sanitized, sanitized);
  }
}

// A path sample that came back non-finite (a degenerate triangle, an overflow)
// is dropped and counted rather than averaged in.
bool giKeepSample(vec3 a, vec3 b) {
  if (giIsFinite(a) && giIsFinite(b)) return true;
  giSanitizedPixels++;
  return false;
}

#endif
