// What the temporal passes share: the test a history texel must pass to
// count for this pixel, and A-SVGF's temporal gradients (Schied et al. 2018).
//
// Temporal gradients: in every GI_GRADIENT_TILE² tile one pixel, picked at
// random each frame, traces one more path with the random numbers the first
// path of the pixel it reprojects to (the nearest one) had last frame
// (gi_temporal_gradient.comp, a dispatch over tiles, so that only tiles pay
// for the extra path). Where nothing changed the two samples are equal, bit
// for bit with a still camera; where the light changed they differ by that
// change, without noise. (A-SVGF's gradient sample is also the pixel's
// sample for the frame; a repeated sample adds nothing new, and measured
// here that cost up to 30% more error in steady state, so the module pays
// one path per tile instead.) The tile stores the
// change and the larger of the two luminances; each pixel then sums both over
// the 3×3 tiles around it and drops the share λ = |Σ change| / Σ max of its
// history (the new frame's weight becomes (1 − λ)·α + λ). A-SVGF projects the
// samples forwards through a visibility buffer so that they land on the very
// same surface point; the module has no such buffer, so the sample is taken
// at this frame's pixel centre: under camera motion up to half a pixel from
// last frame's, and at sharp light edges the change then also counts that
// offset. A-SVGF reconstructs the gradients with an edge-aware à-trous filter;
// here a box over the 3×3 tiles (9×9 pixels).
#ifndef GI_TEMPORAL_GLSL
#define GI_TEMPORAL_GLSL
#include "gi_frame.glsl"
#include "random.glsl"

// The view depth `world` had from the previous camera.
float giPreviousViewDepth(vec3 world) { return -(giFrame.previousCamera.viewFromWorld * vec4(world, 1.0)).z; }

bool giDepthAgrees(float stored, float expected, float tolerance) {
  return stored > 0.0 && abs(stored - expected) <= tolerance * expected;
}

// Last frame's guide (unit normal, view depth / depthScale), GI_BINDING_HISTORY_GUIDE.
// A history guide texel (r32ui): the unit normal octahedral in 2 × 8 bits
// (about half a degree) and view depth / depthScale as a half float, what a
// comparison to a tolerance of several per cent needs. Background: 0.
uint giPackGuide(vec3 n, float scaledDepth) {
  if (!(scaledDepth > 0.0)) return 0u;
  const uvec2 e = uvec2(round((giOctahedralEncode(n) * 0.5 + 0.5) * 255.0));
  return (packHalf2x16(vec2(scaledDepth, 0.0)) & 0xffffu) | (e.x << 16u) | (e.y << 24u);
}
vec4 giUnpackGuide(uint v) {
  if (v == 0u) return vec4(0.0);
  const vec2 e = vec2(uvec2(v >> 16u, v >> 24u) & 255u) / 255.0 * 2.0 - 1.0;
  return vec4(normalize(giOctahedralDecode(e)), unpackHalf2x16(v).x);
}
vec4 giPreviousGuide(ivec2 q) { return giUnpackGuide(imageLoad(giHistoryGuide, q).x); }
// This frame's guide at q, from the G-buffer: what the history guide holds once this frame's is stored.
uint giCurrentGuide(ivec2 q) {
  return giGbCovered(q) ? giPackGuide(giGbNormal(q), giGbViewDepth(q) / giFrame.depthScale) : 0u;
}

// Whether last frame's texel q saw this pixel's surface: its normal within
// the limit, and its depth the one this pixel's point had from the previous
// camera (static geometry) or has now (moving geometry).
bool giHistoryTexelAgrees(vec4 guide, vec3 n, float staticDepth, float depth, float tolerance, float cosNormalLimit) {
  const float stored = guide.w * giFrame.depthScale;
  return (giDepthAgrees(stored, staticDepth, tolerance) || giDepthAgrees(stored, depth, tolerance)) &&
         dot(guide.xyz, n) >= cosNormalLimit;
}

// This frame's light at p as the temporal pass blends it: the reflected
// direct light over the base colour (emission is exact in every frame, and
// the history carries light, not texture: SVGF §4) and the demodulated indirect.
void giNewFrameLight(ivec2 p, out vec3 direct, out vec3 indirect) {
  direct = (giLoadDirect(p) - giGbEmission(p)) / giDirectAlbedo(p);
  indirect = giLoadNoisy(p);
}

// The packed history texel (GI_BINDING_HISTORY_PACKED): the direct light in RGB9E5 (common.glsl),
// values up to 65408 times the scene's typical radiance.
struct GiPackedHistory {
  vec3 direct;   // reflected direct light over the base colour, × GiTemporalPush::historyScale
  vec4 guide;    // unit normal (xyz), view depth / depthScale (w), as giHistoryTexelAgrees reads it
  float frames;  // 0: none
};
uvec2 giPackHistory(GiPackedHistory h) {
  const uvec2 normal = uvec2(round((giOctahedralEncode(h.guide.xyz) * 0.5 + 0.5) * 31.0));
  const uint frames = uint(clamp(h.frames, 0.0, 63.0) + 0.5);
  return uvec2(giPackRgb9e5(h.direct),
               (packHalf2x16(vec2(h.guide.w, 0.0)) & 0xffffu) | (normal.x << 16u) | (normal.y << 21u) | (frames << 26u));
}
GiPackedHistory giUnpackHistory(uvec2 v) {
  const vec2 e = vec2(uvec2(v.y >> 16u, v.y >> 21u) & 31u) / 31.0 * 2.0 - 1.0;
  return GiPackedHistory(giUnpackRgb9e5(v.x), vec4(normalize(giOctahedralDecode(e)), unpackHalf2x16(v.y).x),
                         float(v.y >> 26u));
}

ivec2 giGradientTile(ivec2 p) { return p / int(GI_GRADIENT_TILE); }
ivec2 giGradientTiles() { return (ivec2(giFrame.size) + int(GI_GRADIENT_TILE) - 1) / int(GI_GRADIENT_TILE); }

// The tile's gradient pixel this frame (tiles at the right and bottom edges may be cut short).
ivec2 giGradientPixel(ivec2 tile, uint frameIndex, uint seed) {
  const ivec2 origin = tile * int(GI_GRADIENT_TILE);
  const ivec2 extent = min(ivec2(GI_GRADIENT_TILE), ivec2(giFrame.size) - origin);
  const uint pick = giPcgHash(uint(tile.x) ^ giPcgHash(uint(tile.y) ^ giPcgHash(frameIndex ^ giPcgHash(seed)))) %
                    uint(extent.x * extent.y);
  return origin + ivec2(int(pick) % extent.x, int(pick) / extent.x);
}

// Where the gradient pixel p was last frame: the nearest texel to its
// reprojected centre, if that texel saw the same surface.
bool giGradientSource(ivec2 p, float tolerance, float cosNormalLimit, out ivec2 q) {
  q = ivec2(floor(giPreviousPosition(p)));
  if (!giInPreviousFrame(q)) return false;
  vec3 dir;
  const vec3 world = giGbPosition(p, dir);
  return giHistoryTexelAgrees(giPreviousGuide(q), giGbNormal(p), giPreviousViewDepth(world), giGbViewDepth(p),
                              tolerance, cosNormalLimit);
}

// What a gradient compares: luminance of the direct light over the base colour, and of the demodulated
// indirect.
vec2 giGradientLuminance(vec3 direct, vec3 indirectDemod, ivec2 p) {
  return vec2(giLuminance(direct / giDirectAlbedo(p)), giLuminance(indirectDemod));
}

// With reservoirs no random state repeats the primary hit's light pick, so the gradient sample keeps the
// pick itself, the light and its W (two words, GiGradientSample's z and w): the first path shades with it,
// and last frame's sample, re-shaded with the same pick, repeats bit for bit unless the light moved or
// changed. The pick's shadow ray was the reservoir pass's (W = 0 where it was occluded); the re-shading
// traces none. The sample's two luminances share one word as half floats (giPackGradientLuminance); a
// re-shaded luminance whose half is the kept one's counts as unchanged.
uint giPackGradientLuminance(vec2 luminance) { return packHalf2x16(min(luminance, vec2(65504.0))); }

// λ for direct (x) and indirect (y): the share of the history that pixel p drops.
vec2 giTemporalLambda(ivec2 p) {
  const ivec2 tile = giGradientTile(p), tiles = giGradientTiles();
  vec4 sum = vec4(0.0);
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const ivec2 t = tile + ivec2(i, j);
      if (all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, tiles))) sum += imageLoad(giTemporalGradient, t);
    }
  return vec2(sum.y > 0.0 ? min(abs(sum.x) / sum.y, 1.0) : 0.0, sum.w > 0.0 ? min(abs(sum.z) / sum.w, 1.0) : 0.0);
}

// The filter clamp (TemporalSettings::filterClamp): a filter's result at p
// whose luminance lies further than γ standard deviations from the mean of
// the accumulated light's luminances around p (3×3, surfaces only) is scaled
// back to that bound. As the history grows the accumulated light converges,
// its spread narrows, and the filter can no longer leave a bias its own input
// disproves (light leaking across a shadow, a luminance stop keeping what
// resembles the centre); with a short history the spread is the noise's and
// the filter works as before. TAA's variance clipping (Salvi 2016) applied to
// a spatial filter's output instead of a history.
struct GiLuminanceSpread {
  float mean, sigma;
};
GiLuminanceSpread giSpread(float sum, float squares, float count) {
  const float mean = sum / max(count, 1.0);
  return GiLuminanceSpread(mean, sqrt(max(squares / max(count, 1.0) - mean * mean, 0.0)));
}
// The luminance spread over p's 3×3 neighbourhood (surfaces only) of the direct light over the base colour
// and of the demodulated indirect, from one source: this frame's samples (giNewFrameLight; the history
// clamp's yardstick), svgf's first luminance moments in `set`, or the noisy image the filter read
// (indirect only, direct 0; the filter clamp's).
#define GI_SPREAD_NEW_FRAME 0u
#define GI_SPREAD_MOMENTS 1u
#define GI_SPREAD_NOISY 2u
#define GI_SPREAD_HISTORY 3u  // the indirect history of `set` (the screen filters' input)
void giNeighbourhoodSpread(ivec2 p, uint source, uint set, out GiLuminanceSpread direct,
                           out GiLuminanceSpread indirect) {
  vec2 sum = vec2(0.0), squares = vec2(0.0);  // direct, indirect
  float count = 0.0;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      const ivec2 q = p + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(giFrame.size))) || !giGbCovered(q)) continue;
      vec2 l;
      if (source == GI_SPREAD_NEW_FRAME) {
        vec3 d, ind;
        giNewFrameLight(q, d, ind);
        l = vec2(giLuminance(d), giLuminance(ind));
      } else if (source == GI_SPREAD_MOMENTS) {
        l = giLoadMoments(set, q).mean;
      } else if (source == GI_SPREAD_HISTORY) {
        l = vec2(0.0, giLuminance(giLoadHistoryIndirect(set, q).rgb));
      } else {
        l = vec2(0.0, giLuminance(giLoadNoisy(q)));
      }
      sum += l;
      squares += l * l;
      count += 1.0;
    }
  direct = giSpread(sum.x, squares.x, count);
  indirect = giSpread(sum.y, squares.y, count);
}

vec3 giClampLuminance(vec3 light, GiLuminanceSpread spread, float gamma) {
  const float l = giLuminance(light);
  const float clamped = clamp(l, spread.mean - gamma * spread.sigma, spread.mean + gamma * spread.sigma);
  return l > 0.0 ? light * (clamped / l) : light;
}

#endif
