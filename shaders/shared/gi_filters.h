// Screen-space filters (guided, cross-bilateral, à-trous): their own set 0,
// independent of the scene, so they run on any images (and in tests on
// synthetic ones). Images are rgba32f but the output (FILTER_BINDING_OUTPUT).
#ifndef GI_FILTERS_H
#define GI_FILTERS_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

GPU_CONST FILTER_BINDING_GUIDANCE = 0;  // xyz: normal·0.5+0.5 in [0,1]; w: view depth / depth scale, 0 for
                                        // background (gif's and bilateral's coverage)
GPU_CONST FILTER_BINDING_POSITION = 1;  // xyz: position relative to the camera; w: view depth, 0 for background;
                                        // both in one unit (the module's: the scene extent; AafFilterPush says).
                                        // Read by à-trous, AAF and sspsf only (FilterProgramInfo::readsPositions)
GPU_CONST FILTER_BINDING_INPUT = 2;     // rgb: the noisy image
GPU_CONST FILTER_BINDING_OUTPUT = 3;    // rgb: the filtered image; formatless: the module's indirect output
                                        // (half or single floats, FilterOutputEncoding) or an rgba32f image
GPU_CONST FILTER_BINDING_A = 4;         // FILTER_STACK images at 1/gif.subsample resolution: window statistics, then
                                        // coefficients, box-filtered in place
GPU_CONST FILTER_BINDING_TEMP = 5;      // ping-pong image for à-trous and AAF; the guided filter's coefficient view
GPU_CONST FILTER_BINDING_PARAMS = 6;    // AAF: z_min, z_max (metres), samples, β (metres); formatless (half floats,
                                        // or single floats for the glossy terms, which carry their β in .a)
GPU_CONST FILTER_BINDING_COUNTERS = 7;  // storage buffer: GiCounters (the module's), where the bounds-checked
                                        // variant counts coordinates outside an image (shaders/module/bounds.glsl)
#define FILTER_STACK 8u                 // 32 channels: the 29 window moments of 4-D guidance and RGB input
#define GIF_MAX_RADIUS 128u             // the box filter holds the r most recent originals of its line (gif.radius's range)
#define GIF_MAX_SUBSAMPLE 8u            // gif.subsample's range: statistics pixels of up to 8×8 pixels
#define FILTER_GROUP_SIZE 8u            // 8×8 threads for per-pixel passes
#define FILTER_LINE_GROUP 64u           // 64 rows or columns per group for the box filter

// Moments layout (channel c sits in image c/4, component c%4), each times the
// pixel's weight w (1 covered, 0 background):
//  0..3 guidance I; 4..13 upper triangle of I·Iᵀ (00 01 02 03 11 12 13 22 23 33);
//  14..16 input p (rgb); 17..28 I_i·p_c at 17 + 3i + c; 29 the weight w.
// Coefficients layout, each times the window's covered fraction w̄: 0..11 a at
// 3i + c; 12..14 b (rgb); 15 w̄ itself.
#define GIF_CH_I 0
#define GIF_CH_II 4
#define GIF_CH_P 14
#define GIF_CH_IP 17
#define GIF_CH_WEIGHT 29
#define GIF_MOMENT_IMAGES 8u
#define GIF_COEFF_B 12
#define GIF_COEFF_WEIGHT 15
#define GIF_COEFF_IMAGES 4u

// Bauszat et al. eqs. 3–5: of the four guide rays around an extra eye ray,
// the one most similar in normal and depth, s_i = sn_i · sd_i with
// sn_i = 1 − ‖N_a − N_i‖ / max ‖N_a − N_j‖ and sd_i = 1 − |D_a − D_i| / max |D_a − D_j|.
// The arguments are the norms ‖N_a − N_i‖ and |D_a − D_i| for i = 0..3.
GPU_FN int gifMostSimilarGuide(vec4 normalDistance, vec4 depthDistance) {
  float maxN = max(max(normalDistance[0], normalDistance[1]), max(normalDistance[2], normalDistance[3]));
  float maxD = max(max(depthDistance[0], depthDistance[1]), max(depthDistance[2], depthDistance[3]));
  int best = 0;
  float bestSimilarity = -1.0f;
  for (int i = 0; i < 4; ++i) {
    float sn = maxN > 0.0f ? 1.0f - normalDistance[i] / maxN : 1.0f;
    float sd = maxD > 0.0f ? 1.0f - depthDistance[i] / maxD : 1.0f;
    if (sn * sd > bestSimilarity) {
      bestSimilarity = sn * sd;
      best = i;
    }
  }
  return best;
}

// How the output image holds light: value = radiance × scale, clamped to
// ±limit. The module's indirect output: the pre-exposure and the format's
// largest value; a working rgba32f image: 1 and the largest float.
struct FilterOutputEncoding {
  float scale;
  float limit;
};
GPU_ASSERT_SIZE(FilterOutputEncoding, 8);

struct GuidedMomentsPush {
  uint guidanceDimensions;  // 1 (grey normal), 3 (normal), 4 (normal + depth)
  uint writeCoefficientView;// gif_output: 1 = also write (|a|, |b|) to the temp image
  FilterOutputEncoding encoding;  // of the output image
  uint subsample;   // s: one statistics pixel per s×s pixels (gif.subsample, [1, GIF_MAX_SUBSAMPLE])
  uint pad0;
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(GuidedMomentsPush, 32);

struct BoxPush {
  uint radius;      // window half-size in statistics pixels; windows are clipped at the borders
  uint vertical;    // 0: rows, 1: columns (both in place over the A images)
  uint imageCount;  // how many of the FILTER_STACK images hold data
  uint subsample;   // s: the statistics images cover the render rectangle at 1/s (gifStackSize)
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(BoxPush, 24);

struct GuidedCoefficientsPush {
  float epsilonNormal;  // ridge term for the normal channels (in guidance units²)
  float epsilonDepth;   // ridge term for the depth channel
  uint subsample;       // s, as GuidedMomentsPush's
  uint pad0;
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(GuidedCoefficientsPush, 24);

struct BilateralPush {
  uint radius;          // pixels
  float sigmaSpatial;   // pixels
  float sigmaNormal;    // on |Δ(normal·0.5+0.5)|
  float sigmaDepth;     // on |Δ guidance depth|, relative to the centre's depth
  FilterOutputEncoding encoding;  // of the output image
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(BilateralPush, 32);

struct SspsfPush {  // the input's alpha is 1 where the pixel's primary vertex is a filter vertex
  uint window;          // odd window side in pixels (9 in the thesis)
  float filterWidth;    // pixels: the position kernel's σ is half the HPSF cell size for this width
  float pixelAngle;     // metres per metre of distance per pixel
  float cosNormal;      // neighbours whose normals differ more are not filtered in
  FilterOutputEncoding encoding;  // of the output image
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(SspsfPush, 32);

struct AtrousPush {
  uint iteration;       // 0-based; the tap spacing is 2^iteration
  uint source;          // 0 input, 1 output, 2 temp
  uint destination;     // 1 output, 2 temp
  float sigmaColor;     // colour edge stop at iteration 0; halved every iteration
  float sigmaNormal;    // on |Δ(normal·0.5+0.5)|²
  float sigmaPosition;  // world distance as a fraction of the centre's view depth
  FilterOutputEncoding encoding;  // of the output image
  uvec2 size;       // the render rectangle, pixels (dynamic resolution: the images may be larger); set by the pass
};
GPU_ASSERT_SIZE(AtrousPush, 40);

GPU_NAMESPACE_END
#endif
