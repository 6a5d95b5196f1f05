// Extensions and constants every GI shader uses.
#ifndef GI_COMMON_GLSL
#define GI_COMMON_GLSL
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_nonuniform_qualifier : require

#define GI_PI 3.14159265358979
#define GI_INV_PI 0.318309886183791
#define GI_FLT_MAX 1e30

float giLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
float giMaxComponent(vec3 c) { return max(c.x, max(c.y, c.z)); }
bool giIsFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// Shared-exponent RGB: three values ≥ 0 with `bits` of mantissa each under one 5-bit exponent above
// them, up to 65536 · (1 − 2^-bits). Each mantissa is floor(value / step + dither): a dither of 0.5
// rounds to nearest; one uniform in [0,1) a channel rounds stochastically, which keeps a running mean
// stored this way unbiased (a step smaller than its rounding would never land). 9 bits: RGB9E5
// (EXT_texture_shared_exponent's; the packed history's direct light, a hash cell's recent mean);
// 7 bits: RGB7E5 in 26 bits (a continued path's throughput).
uint giPackRgbShared(vec3 rgb, uint bits, vec3 dither) {
  const float steps = float(1u << bits);
  const vec3 c = clamp(rgb, vec3(0.0), vec3(65536.0 * (steps - 1.0) / steps));
  const float largest = max(c.r, max(c.g, c.b));
  if (!(largest > 0.0)) return 0u;
  int e;
  frexp(largest, e);                     // largest = m · 2^e, m in [0.5, 1): floor(log2) = e − 1
  int exponent = max(e - 1, -16) + 16;   // biased exponent (bias 15) of the largest channel, + 1
  float unit = exp2(float(exponent - 15 - int(bits)));  // the value of one mantissa step
  if (floor(largest / unit + giMaxComponent(dither)) >= steps) {
    exponent += 1;
    unit *= 2.0;
  }
  const uvec3 m = uvec3(min(floor(c / unit + dither), vec3(steps - 1.0)));
  return m.r | (m.g << bits) | (m.b << (2u * bits)) | (uint(exponent) << (3u * bits));
}
vec3 giUnpackRgbShared(uint v, uint bits) {
  const uint mask = (1u << bits) - 1u;
  return vec3(uvec3(v, v >> bits, v >> (2u * bits)) & mask) * exp2(float(int((v >> (3u * bits)) & 31u) - 15 - int(bits)));
}
uint giPackRgb9e5(vec3 rgb) { return giPackRgbShared(rgb, 9u, vec3(0.5)); }
vec3 giUnpackRgb9e5(uint v) { return giUnpackRgbShared(v, 9u); }

// Octahedral unit vectors: the engine's G-buffer normals, the packed history's
// normals and the hash map's directions.
vec2 giOctahedralEncode(vec3 n) {  // n a unit vector; the result in [-1,1]²
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  return n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(n.xy, vec2(0.0)));
}
vec3 giOctahedralDecode(vec2 e) {  // e in [-1,1]²; not normalised
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  float t = max(-n.z, 0.0);
  n.xy += mix(vec2(t), vec2(-t), greaterThanEqual(n.xy, vec2(0.0)));
  return n;
}

// A primary hit's reservoir (reservoirs.glsl) as NEE takes it: the light (x) and its weight W (y, float
// bits). GI_NO_RESERVOIR: NEE picks the point and spot lights itself (every vertex but a primary hit the
// reservoir passes resampled); GI_RESERVOIR_EMPTY: the reservoir found none that reaches the pixel.
// GI_NO_NEE: no next-event estimation at all at this vertex (a primary hit the engine lights itself).
const uvec2 GI_NO_RESERVOIR = uvec2(0xffffffffu, 0u);
const uint GI_RESERVOIR_EMPTY = 0xfffffffeu;
// A reservoir's light with this bit is an emissive triangle's sample point (lights.glsl's
// giPackEmissiveSample); without it (and without GI_RESERVOIR_SKY), a punctual light's index.
const uint GI_RESERVOIR_EMISSIVE = 0x80000000u;
// Bit 30 with bit 31 clear: a direction to the sky (lights.glsl's giPackSkySample). Punctual indices stay
// below it, and the emissive samples and the markers above have bit 31.
const uint GI_RESERVOIR_SKY = 0x40000000u;
const uvec2 GI_NO_NEE = uvec2(0xfffffffdu, 0u);
bool giUsesReservoir(uvec2 reservoir) { return reservoir.x != GI_NO_RESERVOIR.x && reservoir.x != GI_NO_NEE.x; }

#endif
