// Counter-based random numbers: a PCG hash of (pixel, sample, dimension, seed).
// Deterministic and order-independent, so a seed always gives the same image.
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

GiRng giRngCreate(uvec2 pixel, uint sampleIndex, uint seed) {
  GiRng rng;
  rng.state = giPcgHash(pixel.x ^ giPcgHash(pixel.y ^ giPcgHash(sampleIndex ^ giPcgHash(seed))));
  return rng;
}

// Uniform in [0, 1).
float giRandom(inout GiRng rng) {
  rng.state = giPcgHash(rng.state);
  return float(rng.state >> 8) * (1.0 / 16777216.0);
}

vec2 giRandom2(inout GiRng rng) { return vec2(giRandom(rng), giRandom(rng)); }

#endif
