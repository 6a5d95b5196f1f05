// The hash map's packed records (issue 30's memory): anhpsf's continued path in 28 bytes, a cell's recent
// mean in one word and what its sentinel saw in another lose no more than shared/hash_grid.h and hpsf.glsl
// say, and the recent mean, rounded stochastically, still follows frames that move it by less than a step.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "compute_program.h"
#include "descriptors.h"
#include "gpu_test.h"
#include "shared/hash_grid.h"
#include "shared/walk_pack.h"
#include "walk_pack.comp.h"

namespace {

// The octahedral code's direction (hpsf.glsl's hgUnpackDirection, the oracle's own copy).
std::array<double, 3> decodeDirection(uint32_t packed) {
  auto snorm = [](uint32_t bits) { return std::max(double(int16_t(uint16_t(bits))) / 32767.0, -1.0); };
  double x = snorm(packed), y = snorm(packed >> 16), z = 1.0 - std::abs(x) - std::abs(y);
  if (z < 0.0) {
    const double ox = x, oy = y;
    x = (1.0 - std::abs(oy)) * (ox >= 0.0 ? 1.0 : -1.0);
    y = (1.0 - std::abs(ox)) * (oy >= 0.0 ? 1.0 : -1.0);
  }
  const double length = std::sqrt(x * x + y * y + z * z);
  return {x / length, y / length, z / length};
}

}  // namespace

class WalkPackTest : public GpuTest {
 protected:
  // Runs walk_pack.comp over `walks` and `means` (the same count) and `sentinels`, in place.
  void run(std::vector<gpu::HgWalk>& walks, std::vector<gpu::WpMean>& means, uint32_t frames, float radianceScale,
           std::vector<gpu::WpSentinel>& sentinels) {
    ASSERT_EQ(walks.size(), means.size());
    const engine::Binding bindings[] = {{gpu::WP_BINDING_WALKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                        {gpu::WP_BINDING_MEANS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                        {gpu::WP_BINDING_SENTINELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
    std::string error;
    engine::DescriptorSet set = engine::createDescriptorSet(ctx, bindings, error);
    const size_t walkBytes = walks.size() * sizeof(gpu::HgWalk), meanBytes = means.size() * sizeof(gpu::WpMean);
    const size_t sentinelBytes = sentinels.size() * sizeof(gpu::WpSentinel);
    engine::Buffer walkBuffer =
        engine::createBuffer(ctx, std::max<size_t>(walkBytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             engine::MemoryKind::HostVisible, error);
    engine::Buffer meanBuffer =
        engine::createBuffer(ctx, std::max<size_t>(meanBytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             engine::MemoryKind::HostVisible, error);
    engine::Buffer sentinelBuffer =
        engine::createBuffer(ctx, std::max<size_t>(sentinelBytes, 4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             engine::MemoryKind::HostVisible, error);
    ASSERT_EQ(error, "");
    std::memcpy(walkBuffer.mapped, walks.data(), walkBytes);
    std::memcpy(meanBuffer.mapped, means.data(), meanBytes);
    std::memcpy(sentinelBuffer.mapped, sentinels.data(), sentinelBytes);
    engine::DescriptorWriter(set.set)
        .buffer(gpu::WP_BINDING_WALKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, walkBuffer.buffer)
        .buffer(gpu::WP_BINDING_MEANS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, meanBuffer.buffer)
        .buffer(gpu::WP_BINDING_SENTINELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sentinelBuffer.buffer)
        .write(ctx.vk);
    VkDescriptorSetLayout layouts[] = {set.layout};
    engine::ComputeProgram program =
        engine::createComputeProgram(ctx, spv_walk_pack_comp, layouts, sizeof(gpu::WpPush), {64, 1}, error);
    ASSERT_EQ(error, "");
    const uint32_t count = uint32_t(walks.size()), sentinelCount = uint32_t(sentinels.size());
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      engine::dispatch(ctx, cmd, program, std::span(&set.set, 1), {std::max(count, sentinelCount), 1},
                       gpu::WpPush{count, frames, radianceScale, sentinelCount});
      engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                            VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    std::memcpy(walks.data(), walkBuffer.mapped, walkBytes);
    std::memcpy(means.data(), meanBuffer.mapped, meanBytes);
    std::memcpy(sentinels.data(), sentinelBuffer.mapped, sentinelBytes);
    engine::destroyComputeProgram(ctx, program);
    engine::destroyBuffer(ctx, sentinelBuffer);
    engine::destroyBuffer(ctx, meanBuffer);
    engine::destroyBuffer(ctx, walkBuffer);
    engine::destroyDescriptorSet(ctx, set);
  }
  void run(std::vector<gpu::HgWalk>& walks, std::vector<gpu::WpMean>& means, uint32_t frames, float radianceScale) {
    std::vector<gpu::WpSentinel> none;
    run(walks, means, frames, radianceScale, none);
  }
};

TEST_F(WalkPackTest, AContinuedPathComesBackWithinItsRecordsSteps) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<uint32_t> word;
  std::vector<gpu::HgWalk> walks(4096), in;
  for (size_t i = 0; i < walks.size(); ++i) {
    gpu::HgWalk& w = walks[i];
    w.origin = {unit(rng) * 200.0f - 100.0f, unit(rng) * 2e-3f, -1e4f * unit(rng)};
    w.index = word(rng);
    w.key = word(rng) | 1u;
    // A diffuse walk's throughput is exactly 1; after glossy vertices, a colour up to 4.
    w.throughput = i % 4 == 0 ? gpu::vec3{1.0f, 1.0f, 1.0f} : gpu::vec3{4 * unit(rng), 4 * unit(rng), unit(rng)};
    w.direction = word(rng);                                            // any pair of snorms is an octahedral code
    w.travel = i % 5 == 0 ? 0.0f : std::exp(unit(rng) * 16.0f - 6.0f);  // 2.5 mm to 22 km
    const int lod = int(word(rng) % 64) - 32;
    w.state = (word(rng) % 18) | (i % 3 == 0 ? 0x10000u : 0u) | uint32_t(lod + 128) << 24;
    w.pad0 = 0;
  }
  in = walks;
  std::vector<gpu::WpMean> means(walks.size(), gpu::WpMean{});
  run(walks, means, 0, 1.0f);
  double worstAngle = 0, worstThroughput = 0, worstTravel = 0;
  for (size_t i = 0; i < walks.size(); ++i) {
    const gpu::HgWalk &a = in[i], &b = walks[i];
    SCOPED_TRACE(i);
    EXPECT_EQ(std::memcmp(&a.origin, &b.origin, sizeof(a.origin)), 0) << "the origin as it was";
    EXPECT_EQ(b.key, a.key);
    EXPECT_EQ(b.index, a.index & ((1u << gpu::HG_WALK_INDEX_BITS) - 1u)) << "all the probes read of the index";
    EXPECT_EQ(b.state, a.state) << "vertices, the continue flag and the level of detail";
    const auto da = decodeDirection(a.direction), db = decodeDirection(b.direction);
    worstAngle = std::max(worstAngle, std::acos(std::min(1.0, da[0] * db[0] + da[1] * db[1] + da[2] * db[2])));
    const float largest = std::max({a.throughput.x, a.throughput.y, a.throughput.z});
    for (int c = 0; c < 3; ++c)
      worstThroughput =
          std::max(worstThroughput, double(std::abs((&b.throughput.x)[c] - (&a.throughput.x)[c])) / largest);
    if (a.throughput.x == 1.0f && a.throughput.y == 1.0f && a.throughput.z == 1.0f) {
      EXPECT_TRUE(b.throughput.x == 1.0f && b.throughput.y == 1.0f && b.throughput.z == 1.0f) << "a diffuse walk's 1";
    }
    if (a.travel == 0.0f) {
      EXPECT_EQ(b.travel, 0.0f);
    } else {
      worstTravel = std::max(worstTravel, double(std::abs(b.travel - a.travel)) / a.travel);
    }
  }
  std::printf("worst: direction %.4f°, throughput %.3f%% of its largest channel, travel %.3f%%\n",
              worstAngle * 180 / M_PI, worstThroughput * 100, worstTravel * 100);
  EXPECT_LE(worstAngle * 180 / M_PI, 0.03) << "2 × 13-bit octahedral";
  EXPECT_LE(worstThroughput, 1.0 / 128 * (1 + 1e-3))
      << "7-bit mantissas, the largest channel's at least 64, rounded to nearest";
  EXPECT_LE(worstTravel, 1.0 / 128 + 1.0 / 2048) << "a half float's 10-bit mantissa, then 6 bits, each rounded";
}

TEST_F(WalkPackTest, ALevelOfDetailBeyondItsBitsIsClampedAndDepthIsKept) {
  std::vector<gpu::HgWalk> walks(4, gpu::HgWalk{});
  const int lods[] = {-100, -32, 31, 90};
  for (size_t i = 0; i < walks.size(); ++i) walks[i].state = 17u | uint32_t(lods[i] + 128) << 24;
  std::vector<gpu::WpMean> means(walks.size(), gpu::WpMean{});
  run(walks, means, 0, 1.0f);
  const int expected[] = {-32, -32, 31, 31};
  for (size_t i = 0; i < walks.size(); ++i) {
    EXPECT_EQ(int(walks[i].state >> 24) - 128, expected[i]);
    EXPECT_EQ(walks[i].state & 0xffffu, 17u);
  }
}

// A mean 0.4% below its target, blended 1/64 of the way a frame: each frame moves it by 6e-5, a sixtieth
// of RGB9E5's step at 1. Rounded to nearest it would never move; rounded stochastically every cell gets
// there within a step, and the cells' average within 0.003% (a dither of 10 bits a channel stops 0.01%
// short: the last step's remainder moves it by less than 1/1024 of a step a frame).
TEST_F(WalkPackTest, ARecentMeanMovedByLessThanAStepStillReachesItsTarget) {
  const uint32_t cells = 16384, frames = 1200;
  const float radianceScale = 0.25f;  // the cell holds radiance · 0.25: radiance 4 is 1 packed
  std::vector<gpu::WpMean> means(cells);
  for (uint32_t i = 0; i < cells; ++i)
    means[i] = gpu::WpMean{{4.0f, 2.0f, 0.5f}, 1.0f / 64.0f, {4.016f, 2.008f, 0.502f}, i * 7919u, {}, 0};
  std::vector<gpu::HgWalk> walks(cells, gpu::HgWalk{});
  run(walks, means, frames, radianceScale);
  double sum[3] = {}, worst = 0;
  for (const gpu::WpMean& m : means)
    for (int c = 0; c < 3; ++c) {
      sum[c] += (&m.result.x)[c];
      worst = std::max(worst, double(std::abs((&m.result.x)[c] - (&m.target.x)[c])) / m.target.x);
    }
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / cells, target = (&means[0].target.x)[c];
    std::printf("channel %d: mean of the cells %.6f, target %.6f (start %.6f)\n", c, mean, target,
                (&means[0].start.x)[c]);
    EXPECT_NEAR(mean, target, 3e-5 * means[0].target.x) << "channel " << c;
  }
  EXPECT_LE(worst, 1.0 / 256) << "each cell within a step of its largest channel";
}

// What a sentinel saw, as a cell keeps it (two half floats): a static scene's re-trace, which finds the same
// floats, reads as no change; a hit that moved by 0.1% of its distance or more, or a ray that hit and now
// misses, is another hit (the change at least the cell's mean); a light that changed is its change within a
// half's step, in the cell's units; light beyond a half's range is held at its largest, not infinity; and
// only no sentinel at all packs to 0.
TEST_F(WalkPackTest, ASentinelsAnswersComeBackAsHalfFloatsAndCompareAsTheCheckAsks) {
  const float scale = 0.25f;  // radiance 4 is 1 in the map's units
  const float mean = 0.7f;
  struct Case {
    float dThen, lThen, dNow, lNow;
    float expected;   // the change hgSentinelChange should give
    float tolerance;  // absolute: a half's step of the lights (at most 2^-10 of each), 0 = exact
  };
  const Case cases[] = {
      {3.7f, 0.42f, 3.7f, 0.42f, 0.0f, 0.0f},                    // static: the same floats
      {-1.0f, 0.0f, -1.0f, 0.0f, 0.0f, 0.0f},                    // missed both times
      {3.7f, 0.42f, 3.7f * 1.001f, 0.42f, mean, 0.0f},           // moved by 0.1%: another hit
      {37.0f, 2.0f, 37.0f * 0.998f, 2.0f, mean, 0.0f},           // 0.2% closer, farther away
      {3.7f, 0.42f, -1.0f, 0.0f, mean, 0.0f},                    // hit, then missed: at least the mean
      {3.7f, 0.42f, 3.7f, 0.42f * 1.1f, 0.042f, 0.462f / 1024},  // the light 10% brighter
      {3.7f, 2.0f, 3.7f * 1.01f, 1.0f, 1.0f, 2.0f / 1024},       // another hit whose light fell by more than the mean
      {3.7f, 1e9f, 3.7f, 1e9f, 0.0f, 0.0f},                      // beyond a half's range, unchanged
  };
  std::vector<gpu::WpSentinel> sentinels;
  for (const Case& c : cases) sentinels.push_back({c.dThen, c.lThen, c.dNow, c.lNow, mean, 0u, -1.0f, 0u});
  sentinels.push_back({0.0f, 0.0f, 0.0f, 0.0f, mean, 0u, -1.0f, 0u});    // no sentinel
  sentinels.push_back({1e-3f, 0.0f, 1e-3f, 0.0f, mean, 0u, -1.0f, 0u});  // a hit at 1 mm that sees no light
  std::vector<gpu::HgWalk> walks;
  std::vector<gpu::WpMean> means;
  run(walks, means, 0, scale, sentinels);
  for (size_t i = 0; i < std::size(cases); ++i) {
    SCOPED_TRACE(i);
    EXPECT_TRUE(std::isfinite(sentinels[i].change));
    if (cases[i].tolerance == 0.0f) {
      EXPECT_EQ(sentinels[i].change, cases[i].expected);
    } else {
      EXPECT_NEAR(sentinels[i].change, cases[i].expected, cases[i].tolerance);
    }
  }
  EXPECT_EQ(sentinels[std::size(cases)].seenThen, 0u) << "no sentinel packs to 0";
  EXPECT_NE(sentinels[std::size(cases) + 1].seenThen, 0u) << "a real hit does not read as no sentinel";
  EXPECT_EQ(sentinels[7].seenThen >> 16, 0x7bffu) << "light beyond a half's range is held at 65504, not infinity";
}
