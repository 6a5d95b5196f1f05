// The hash map's CPU-visible pieces (shared/hash_grid.h, the same code the
// shaders run): hashing, descriptors, jitter, LOD and fixed point.
#include <gtest/gtest.h>
#include <numbers>

#include <algorithm>
#include <random>
#include <set>

#include "gi/settings.h"
#include "shared/hash_grid.h"

using gpu::HgDescriptor;

// Known answers, computed apart from this code (a few lines of Python from
// the published definitions: PCG-RXS-M-XS as Jarzynski & Olano 2020 give it,
// MurmurHash3's fmix32, and the chaining hash_grid.h documents).
TEST(HashGridMath, HashesGiveTheirKnownAnswersAndDifferBetweenFunctions) {
  EXPECT_EQ(gpu::hgHashPcg(0u), 129708002u);
  EXPECT_EQ(gpu::hgHashPcg(1u), 2831084092u);
  EXPECT_EQ(gpu::hgHashMurmur(0u), 0u);
  EXPECT_EQ(gpu::hgHashMurmur(1u), 0x514e28b7u);
  HgDescriptor d{12, -7, 300, -3, 5};
  EXPECT_EQ(gpu::hgIndexHash(d), 162668298u);
  EXPECT_EQ(gpu::hgVerificationKey(d), 2712074955u);
  EXPECT_NE(gpu::hgIndexHash(d), gpu::hgVerificationKey(d));
  // Over many descriptors: keys are never empty, and the two hashes are unrelated
  // (descriptors sharing an index hash almost never share a verification key).
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  size_t sameLowBits = 0;
  for (int x = -20; x < 20; ++x)
    for (int y = -20; y < 20; ++y)
      for (int lod = -2; lod < 2; ++lod) {
        HgDescriptor e{x, y, 7, lod, 0};
        uint32_t index = gpu::hgIndexHash(e), key = gpu::hgVerificationKey(e);
        EXPECT_NE(key, gpu::HG_EMPTY_KEY);
        pairs.insert({index, key});
        sameLowBits += (index & 0xffffu) == (key & 0xffffu);
      }
  EXPECT_EQ(pairs.size(), 40u * 40u * 4u);  // no two cells collide in both hashes
  EXPECT_LT(sameLowBits, 5u);
  // Changing any field changes the key.
  HgDescriptor f = d;
  f.normalBits = 6;
  EXPECT_NE(gpu::hgVerificationKey(f), gpu::hgVerificationKey(d));
  f = d;
  f.lod = -2;
  EXPECT_NE(gpu::hgIndexHash(f), gpu::hgIndexHash(d));
}

// Alg. 3's jitter: δ uniform in [−1, 1]³ with its normal part removed, times
// j cells: ±j cells in the tangent plane (for an axis-aligned normal, the
// full ±j·cell along each tangent axis), zero mean.
TEST(HashGridMath, JitterSpansPlusMinusJCellsInTheTangentPlaneWithZeroMean) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float j = 0.6f, cell = 2.0f;
  for (glm::vec3 n : {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(1, 2, -3)), glm::vec3(1, 0, 0)}) {
    glm::dvec3 sum(0.0);
    glm::vec3 reach(0.0f);
    const int count = 20000;
    for (int i = 0; i < count; ++i) {
      glm::vec3 o = gpu::hgJitter(n, glm::vec3(u(rng), u(rng), u(rng)), j, cell);
      EXPECT_NEAR(glm::dot(o, n), 0.0f, 1e-5f);
      EXPECT_LE(glm::length(o), j * cell * std::sqrt(3.0f) + 1e-5f);  // |δ| ≤ √3
      reach = glm::max(reach, glm::abs(o));
      sum += glm::dvec3(o);
    }
    EXPECT_LT(glm::length(sum / double(count)), 0.02);  // 0.6·2·0.58/√20000 ≈ 0.005 per axis
    if (n.z == 1.0f) {
      EXPECT_GT(reach.x, 0.99f * j * cell);  // the whole ±j cells, not ±j/2
      EXPECT_GT(reach.y, 0.99f * j * cell);
    }
  }
}

// The segment's travel is its L∞ length (Alg. 3), not the Euclidean one.
TEST(HashGridMath, TravelIsTheLInfinityLength) {
  EXPECT_FLOAT_EQ(gpu::hgLinf(glm::vec3(0), glm::vec3(3, -4, 1)), 4.0f);
  EXPECT_FLOAT_EQ(gpu::hgLinf(glm::vec3(1, 1, 1), glm::vec3(1, 1, -2)), 3.0f);
}

// Meijer §4.2.2: b normal bits give 2^b bins in all. Every bit count fills
// exactly its 2^b bins over the sphere, and the normals of axis-aligned walls
// sit at least a tenth of a bin's angular width from any bin edge (the
// rotated frame), so one wall's samples share one bin. Jitter spreads a normal over the bins
// around it and keeps it a unit vector.
TEST(HashGridMath, NormalBitsGiveTwoToTheBBinsAndWallsSitInsideThem) {
  std::vector<glm::vec3> sphere;
  const int rings = 200;
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < 2 * rings; ++k) {
      float theta = std::numbers::pi_v<float> * (i + 0.5f) / rings, phi = std::numbers::pi_v<float> * k / rings;
      sphere.push_back({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  const glm::vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  EXPECT_EQ(gpu::hgNormalBits(axes[0], 0), 0u);
  for (uint32_t b = 1; b <= HG_MAX_NORMAL_BITS; ++b) {
    std::set<uint32_t> bins;
    for (glm::vec3 n : sphere) bins.insert(gpu::hgNormalBits(n, b));
    EXPECT_EQ(bins.size(), size_t(1) << b) << b << " bits";
    for (glm::vec3 a : axes) {
      // Tilting the normal by a tenth of a bin's angular width √(4π/2^b) in any direction keeps its bin.
      float tilt = 0.1f * std::sqrt(4.0f * std::numbers::pi_v<float> / float(1u << b));
      glm::vec3 t, bt;
      gpu::hgTangents(a, t, bt);
      for (int k = 0; k < 16; ++k) {
        float phi = 2.0f * std::numbers::pi_v<float> * k / 16.0f;
        glm::vec3 tilted = glm::normalize(a + std::tan(tilt) * (std::cos(phi) * t + std::sin(phi) * bt));
        EXPECT_EQ(gpu::hgNormalBits(tilted, b), gpu::hgNormalBits(a, b)) << b << " bits, axis " << a.x << a.y << a.z;
      }
    }
  }
  // Three bits: the six walls of a box land in six different bins.
  std::set<uint32_t> walls;
  for (glm::vec3 a : axes) walls.insert(gpu::hgNormalBits(a, 3));
  EXPECT_EQ(walls.size(), 6u);
  // Normal jitter: unit length, and with a bin's width of jitter a wall's samples reach other bins.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::set<uint32_t> reached;
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 n = gpu::hgJitterNormal(axes[2], glm::vec2(u(rng), u(rng)), 1.0f, 4);
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    reached.insert(gpu::hgNormalBits(n, 4));
  }
  EXPECT_GT(reached.size(), 1u);
  EXPECT_EQ(gpu::hgJitterNormal(axes[2], glm::vec2(0.9f, 0.1f), 0.0f, 4), axes[2]);
}

TEST(HashGridMath, LodRisesMonotonicallyWithDistance) {
  int previous = -1000;
  for (float travel = 0.01f; travel < 1e5f; travel *= 1.3f) {
    int lod = gpu::hgLod(16.0f * 0.002f, travel, 0.0f);
    EXPECT_GE(lod, previous);
    previous = lod;
  }
  // The cell is the footprint rounded down to a power of two: 16 px · 0.002 · 10 m = 0.32 m → 0.25 m.
  EXPECT_EQ(gpu::hgLod(16.0f * 0.002f, 10.0f, 0.0f), -2);
  // Stochastic LOD picks the upper level in proportion to the fractional part.
  int upper = 0;
  for (int i = 1; i <= 1000; ++i) upper += gpu::hgLod(16.0f * 0.002f, 10.0f, float(i) / 1001.0f) == -1;
  float fraction = std::log2(0.32f) - std::floor(std::log2(0.32f));  // 0.356
  EXPECT_NEAR(upper / 1000.0f, fraction, 0.01f);
}

TEST(HashGridMath, CoordinatesFarFromTheOriginQuantiseWithoutOverflowOrAliasing) {
  glm::vec3 n(0, 1, 0);
  for (float far : {1e3f, 1e4f, 1e5f, -1e5f}) {
    // A fine level: cells of 1/64 m; points 1 m apart must stay in different cells.
    HgDescriptor a = gpu::hgDescriptor(glm::vec3(far, 2.0f, far), n, -6, 0);
    HgDescriptor b = gpu::hgDescriptor(glm::vec3(far + 1.0f, 2.0f, far), n, -6, 0);
    EXPECT_NE(a.x, b.x) << far;
    EXPECT_EQ(a.lod, -6);
    EXPECT_LT(std::abs(double(a.x)), HG_COORD_LIMIT);
    // An absurdly fine level is raised until the coordinates fit in int32.
    HgDescriptor c = gpu::hgDescriptor(glm::vec3(far, 0.0f, 0.0f), n, -40, 0);
    EXPECT_GT(c.lod, -40);
    EXPECT_LT(std::abs(double(c.x)), 2.0 * HG_COORD_LIMIT);
    EXPECT_NE(gpu::hgVerificationKey(a), gpu::hgVerificationKey(b));
  }
}

TEST(HashGridMath, FixedPointSumsDoNotDependOnOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1000.0f);
  std::vector<float> values(5000);
  for (float& v : values) v = u(rng) * u(rng) / 1000.0f;
  uint64_t reference = 0;
  for (float v : values) reference += gpu::hgToFixed(v);
  for (int shuffle = 0; shuffle < 20; ++shuffle) {
    std::shuffle(values.begin(), values.end(), rng);
    uint64_t sum = 0;
    for (float v : values) sum += gpu::hgToFixed(v);
    EXPECT_EQ(sum, reference);
  }
  double exact = 0.0;
  for (float v : values) exact += v;
  EXPECT_NEAR(gpu::hgFromFixed(reference, uint32_t(values.size())), exact / values.size(), 1e-3);
  // Negative or huge values clamp instead of wrapping.
  EXPECT_EQ(gpu::hgToFixed(-5.0f), 0u);
  EXPECT_EQ(gpu::hgToFixed(1e30f), gpu::hgToFixed(float(HG_MAX_SAMPLE)));
}

// The map's size and the n-methods' cell widths (gi/settings.h): a quarter cell a pixel; nhpsf and anhpsf
// get a third of a cell a vertex their paths reach (pixels × segments / 3) up to 2^19 cells, and past
// that, or in a smaller map set by hand, widen their later cells by powers of two until that need fits,
// never below the width asked for; hpsf keeps the width asked for.
TEST(HashGridMath, TheNMethodsMapFollowsTheirVerticesAndTheirLaterCellsWidenPastItsCap) {
  gi::Settings s;
  s.method = gi::Method::Hpsf;
  EXPECT_EQ(gi::hashCapacity(s, 160, 90), 4096u);
  EXPECT_EQ(gi::hashCapacity(s, 1920, 1080), 1u << 19);
  EXPECT_EQ(gi::hashSecondaryWidth(s, 1920, 1080), 1.0f);
  s.method = gi::Method::Nhpsf;  // 3 segments: 14,400 cells' worth at 160×90
  EXPECT_EQ(gi::hashCapacity(s, 160, 90), 1u << 14);
  EXPECT_EQ(gi::hashSecondaryWidth(s, 160, 90), 1.0f);
  EXPECT_EQ(gi::hashCapacity(s, 1920, 1080), 1u << 19);    // 2.07M wanted: the cap
  EXPECT_EQ(gi::hashSecondaryWidth(s, 1920, 1080), 4.0f);  // 2.07M ≤ 4 × 2^19
  s.method = gi::Method::Anhpsf;                           // 4 segments
  EXPECT_EQ(gi::hashCapacity(s, 160, 90), 1u << 15);
  EXPECT_EQ(gi::hashSecondaryWidth(s, 1920, 1080), 8.0f);  // 2.76M
  s.hpsf.samplesPerPixel = 16;  // the samples a pixel change neither (the ray budget changes them every frame)
  EXPECT_EQ(gi::hashCapacity(s, 160, 90), 1u << 15);
  EXPECT_EQ(gi::hashSecondaryWidth(s, 1920, 1080), 8.0f);
  s.hpsf.continuationDepth = 16;  // 11M: the width stops at 16
  EXPECT_EQ(gi::hashSecondaryWidth(s, 1920, 1080), 16.0f);
  s.hpsf.continuationDepth = 4;
  s.hpsf.samplesPerPixel = 1;
  s.method = gi::Method::Nhpsf;
  s.hpsf.capacity = 4096;  // set by hand below the need: wider
  EXPECT_EQ(gi::hashCapacity(s, 160, 90), 4096u);
  EXPECT_EQ(gi::hashSecondaryWidth(s, 160, 90), 4.0f);
  s.hpsf.secondaryWidthScale = 3.0f;
  EXPECT_EQ(gi::hashSecondaryWidth(s, 160, 90), 4.0f);
  s.hpsf.capacity = 1u << 14;  // one that holds them: the width asked for
  EXPECT_EQ(gi::hashSecondaryWidth(s, 160, 90), 3.0f);
  s.method = gi::Method::Hpsf;
  s.hpsf.capacity = 4096;
  EXPECT_EQ(gi::hashSecondaryWidth(s, 160, 90), 3.0f);
}
