// SVGF's edge-stopping functions (Schied et al. 2017, eqs. 3–5), shared by the
// variance estimate and the à-trous iterations, over the guide image the
// variance pass writes: the G-buffer's unit normal and view depth, one load a tap.
#ifndef GI_SVGF_GLSL
#define GI_SVGF_GLSL
#include "gi_frame.glsl"

bool svgfInside(ivec2 q) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(giFrame.size))); }

// Normal (xyz) and view depth (w; 0 outside the image or where there is no surface).
vec4 svgfGuide(ivec2 q) { return svgfInside(q) ? imageLoad(giSvgfGuide, q) : vec4(0.0); }

// The view depth's screen-space gradient at p (per pixel) from the depths
// around it: central differences, one-sided beside an edge of the surface.
vec2 svgfDepthGradient(ivec2 p, float z) {
  vec2 g;
  for (int axis = 0; axis < 2; ++axis) {
    const ivec2 d = axis == 0 ? ivec2(1, 0) : ivec2(0, 1);
    const float a = svgfGuide(p + d).w, b = svgfGuide(p - d).w;
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

#endif
