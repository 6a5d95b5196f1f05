// Counter-based random numbers: a PCG hash of (pixel, sample, seed, stream).
// Deterministic and order-independent, so a seed always gives the same image.
// Each consumer has its own stream, so the module's samples never repeat the
// reference's (which would hide their error when the two are compared).
#ifndef GI_RANDOM_GLSL
#define GI_RANDOM_GLSL

uint giPcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

struct GiRng {
  uint state;
};

#define GI_STREAM_REFERENCE 0u
#define GI_STREAM_MODULE 1u
#define GI_STREAM_SUPERSAMPLE 2u
#define GI_STREAM_AAF 3u
#define GI_STREAM_HASH 4u
#define GI_STREAM_RESERVOIRS 5u
#define GI_STREAM_RESERVOIR_GROUPS 6u  // the 8×8 groups' shared candidates (gi_reservoirs.comp)

GiRng giRngCreate(uvec2 pixel, uint sampleIndex, uint seed, uint stream) {
  GiRng rng;
  rng.state = giPcgHash(pixel.x ^ giPcgHash(pixel.y ^ giPcgHash(sampleIndex ^ giPcgHash(seed ^ giPcgHash(stream)))));
  return rng;
}

// Uniform in [0, 1).
float giRandom(inout GiRng rng) {
  rng.state = giPcgHash(rng.state);
  return float(rng.state >> 8) * (1.0 / 16777216.0);
}

vec2 giRandom2(inout GiRng rng) { return vec2(giRandom(rng), giRandom(rng)); }

#endif
