// SVGF's edge-stopping functions (Schied et al. 2017, eqs. 3–5), shared by the
// variance estimate and the à-trous iterations, and the images they work in.
//
// The guide of a tap is this frame's history guide (temporal.glsl's
// giPackGuide: the unit normal octahedral in 2 × 8 bits, view depth over the
// scene extent as a half float), one 32-bit load. The variance pass stores it
// (the temporal pass has read last frame's by then) and so packs its own taps
// from the G-buffer, the same values; the à-trous iterations load it. Measured against the
// G-buffer's normal and depth at full precision (three loads and the depth's
// decode per tap): the same error on Sponza, +0.14% on Cornell, and the
// à-trous iterations a quarter faster (RESULTS, "svgf in its own outputs").
//
// The light the iterations filter ping-pongs between two pairs of images
// that hold nothing else meanwhile: the outputs (written last, remodulated)
// and the history set the temporal pass read this frame (last frame's: the
// next frame's temporal pass rewrites it whole). Each holds demodulated light
// (rgb) and its luminance variance (a) in its own units (outputScale,
// historyScale), and only where there is a surface: the outputs keep the
// background the trace wrote, and the direct output its exact light when
// the direct light is not filtered.
#ifndef GI_SVGF_GLSL
#define GI_SVGF_GLSL
#include "temporal.glsl"

bool svgfInside(ivec2 q) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(giFrame.size))); }

// Normal (xyz) and view depth / depthScale (w; 0 outside the image or where there is no surface) of
// this frame's pixel q: from the history guide once `stored` (the à-trous iterations), else packed from
// the G-buffer (the variance pass, which stores it). The weights compare depths by their ratios: the
// scale does not matter.
vec4 svgfGuide(ivec2 q, bool stored) {
  if (!svgfInside(q)) return vec4(0.0);
  return giUnpackGuide(stored ? imageLoad(giHistoryGuide, q).x : giCurrentGuide(q));
}

// The view depth's screen-space gradient at p (per pixel) from the depths
// around it: central differences, one-sided beside an edge of the surface.
vec2 svgfDepthGradient(ivec2 p, float z, bool stored) {
  vec2 g;
  for (int axis = 0; axis < 2; ++axis) {
    const ivec2 d = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
    const float a = svgfGuide(p + d, stored).w, b = svgfGuide(p - d, stored).w;
    g[axis] = a > 0.0 && b > 0.0 ? 0.5 * (a - b) : a > 0.0 ? a - z : b > 0.0 ? z - b : 0.0;
  }
  return g;
}

// The weight of a tap's geometry: depth (eq. 3: σ_z local gradients along
// the offset, with a floor of 0.1% of the depth so surfaces seen flat on do
// not divide by zero) times normal (eq. 4: max(0, n·n')^σ_n).
float svgfGeometryWeight(vec4 centre, vec2 gradient, vec4 tap, vec2 offset, float sigmaDepth, float sigmaNormal) {
  const float depth = abs(centre.w - tap.w) / (sigmaDepth * abs(dot(gradient, offset)) + 1e-3 * centre.w);
  return pow(max(0.0, dot(centre.xyz, tap.xyz)), sigmaNormal) * exp(-depth);
}

// --- The ping-pong pairs.
const uint SVGF_OUTPUTS = 0u, SVGF_SCRATCH = 1u;

// The pair iteration `iteration` of `iterations` reads (the variance estimate writes the one the
// first reads): the last reads the scratch pair and writes the outputs.
uint svgfReadPair(uint iteration, uint iterations) {
  return iterations == 0u || ((iterations - 1u - iteration) & 1u) == 0u ? SVGF_SCRATCH : SVGF_OUTPUTS;
}

// Demodulated light (rgb) and its luminance variance (a), direct and indirect.
struct SvgfTexel {
  vec4 direct, indirect;
};

vec4 svgfDecode(vec4 v, float scale) { return vec4(v.rgb / scale, v.a / (scale * scale)); }
vec4 svgfEncode(vec4 v, float scale, float limit) {
  return vec4(giOutputEncode(v.rgb, scale, limit), min(v.a * scale * scale, limit));
}

SvgfTexel svgfLoad(uint pair, uint writtenSet, ivec2 q) {
  if (pair == SVGF_OUTPUTS)
    return SvgfTexel(svgfDecode(imageLoad(giOutDirect, q), giFrame.outputScale),
                     svgfDecode(imageLoad(giOutIndirect, q), giFrame.outputScale));
  // The scratch pair: the set the temporal pass did not write this frame.
  const vec4 d = writtenSet == 0u ? imageLoad(giHistoryDirectB, q) : imageLoad(giHistoryDirectA, q);
  const vec4 i = writtenSet == 0u ? imageLoad(giHistoryIndirectB, q) : imageLoad(giHistoryIndirectA, q);
  return SvgfTexel(svgfDecode(d, giFrame.historyScale), svgfDecode(i, giFrame.historyScale));
}

// `direct` 0: the direct light is not filtered, and its image keeps what it holds.
void svgfStore(uint pair, uint writtenSet, ivec2 p, SvgfTexel t, uint direct) {
  if (pair == SVGF_OUTPUTS) {
    if (direct != 0u) imageStore(giOutDirect, p, svgfEncode(t.direct, giFrame.outputScale, giFrame.outputMax));
    imageStore(giOutIndirect, p, svgfEncode(t.indirect, giFrame.outputScale, giFrame.outputMax));
    return;
  }
  const vec4 d = svgfEncode(t.direct, giFrame.historyScale, giFrame.historyMax);
  const vec4 i = svgfEncode(t.indirect, giFrame.historyScale, giFrame.historyMax);
  if (writtenSet == 0u) {
    if (direct != 0u) imageStore(giHistoryDirectB, p, d);
    imageStore(giHistoryIndirectB, p, i);
  } else {
    if (direct != 0u) imageStore(giHistoryDirectA, p, d);
    imageStore(giHistoryIndirectA, p, i);
  }
}

#endif
