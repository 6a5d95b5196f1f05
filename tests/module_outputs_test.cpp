// The module's outputs as an engine reads them: half or single floats
// (ModuleDesc::outputFormat), light × the frame's pre-exposure, clamped into
// the format; pictures (debug views that are not light, aaf_ao) unscaled.
#include <cfloat>
#include <cmath>
#include <cstdio>

#include "module_test_helpers.h"
#include "readback.h"

class ModuleOutputsTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 48;
constexpr uint32_t kFrames = 3;

// The three outputs as stored: the pre-exposure is not divided out.
struct Stored {
  engine::FloatImage direct, indirect, composite;
};

// `frames` frames of `settings` on a new module whose outputs are `format` (its radiance histories
// `history`), pre-exposed by `preExposure`. Use as ASSERT_NO_FATAL_FAILURE(renderOutputs(...)).
void renderOutputs(const engine::Context& ctx, LoadedScene& s, const gi::Settings& settings, VkFormat format,
                   float preExposure, Stored& out, VkFormat history = VK_FORMAT_R16G16B16A16_SFLOAT,
                   uint32_t frames = kFrames, VkFormat composite = VK_FORMAT_UNDEFINED) {
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
  desc.outputFormat = format;
  desc.compositeFormat = composite;
  desc.historyFormat = history;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, settings, session, &desc));
  session.preExposure = preExposure;
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  for (uint32_t f = 0; f < frames; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  const gi::Outputs o = gi::outputs(session.module);
  EXPECT_EQ(o.format, format);
  EXPECT_EQ(o.compositeFormat, composite == VK_FORMAT_UNDEFINED ? format : composite);
  out.direct = readbackRgbOrFail(ctx, o.direct, o.format, {kSize, kSize});
  out.indirect = readbackRgbOrFail(ctx, o.indirect, o.format, {kSize, kSize});
  out.composite = readbackRgbOrFail(ctx, o.composite, o.compositeFormat, {kSize, kSize});
}

// Σ|a − b| / Σ|b|.
double relativeL1(const engine::FloatImage& a, const engine::FloatImage& b) {
  double diff = 0.0, sum = 0.0;
  for (size_t i = 0; i < b.pixels.size(); ++i) {
    diff += std::fabs(double(a.pixels[i]) - double(b.pixels[i]));
    sum += std::fabs(double(b.pixels[i]));
  }
  return sum > 0.0 ? diff / sum : diff;
}

// Values of `packed` against the same outputs of `half`: each within `step` of itself (negative light as
// 0, nothing below 0) and under 1% relative L1.
void expectWithinPackedSteps(const engine::FloatImage& half, const engine::FloatImage& packed, float step,
                             const std::string& what) {
  size_t outside = 0;
  double lit = 0.0;
  for (size_t v = 0; v < half.pixels.size(); ++v) {
    const float expected = std::max(half.pixels[v], 0.0f);
    outside += !(packed.pixels[v] >= 0.0f && std::fabs(packed.pixels[v] - expected) <= expected * step + 1e-4f);
    lit += expected;
  }
  EXPECT_EQ(outside, 0u) << what;
  EXPECT_GT(lit, 0.0) << what << ": nothing to compare";
  const double l1 = relativeL1(packed, half);
  std::printf("%-24s packed vs half, relative L1 %.2e\n", what.c_str(), l1);
  EXPECT_LT(l1, 1e-2) << what;
}

}  // namespace

// Every method gives the same image in half floats as in single floats, to
// half-float rounding: 2^-11 relative per store, a few stores deep (à-trous
// ping-pongs through the output; the hash methods keep their per-pixel sample
// in it until the lookup).
TEST_F(ModuleOutputsTest, HalfFloatOutputsMatchSingleFloatOnes) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const float preExposure = 1.0f / s.gpu.desc.typicalRadiance;
  for (uint32_t i = 0; i < gi::kMethodCount; ++i) {
    gi::Settings settings;
    settings.method = gi::Method(i);
    Stored half, single;
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, VK_FORMAT_R16G16B16A16_SFLOAT, preExposure, half));
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, VK_FORMAT_R32G32B32A32_SFLOAT, preExposure, single));
    const char* name = gi::methodName(settings.method);
    const double direct = relativeL1(half.direct, single.direct), indirect = relativeL1(half.indirect, single.indirect),
                 composite = relativeL1(half.composite, single.composite);
    std::printf("%-9s half vs single, relative L1: direct %.2e, indirect %.2e, composite %.2e\n", name, direct,
                indirect, composite);
    EXPECT_LT(direct, 2e-3) << name << " direct";
    EXPECT_LT(indirect, 2e-3) << name << " indirect";
    EXPECT_LT(composite, 2e-3) << name << " composite";
  }
}

// The engine's HDR format, B10G11R11_UFLOAT_PACK32 (6 mantissa bits in red and green, 5 in blue: a value
// is within 1/64 of itself after one rounding, 1/32 truncated), for the composite alone
// (ModuleDesc::compositeFormat): every method's direct and indirect outputs are bit for bit those of the
// half-float default and its composite theirs to the packed steps (gif's supersampling reads the
// composite and rounds again: 1/16); and for all three outputs (ModuleDesc::outputFormat): the passes
// work in the module's half-float pair, so the direct and indirect outputs are the half-float ones after
// one rounding and the composite as before. A format the module does not take is a named error.
TEST_F(ModuleOutputsTest, PackedOutputsAreTheHalfFloatOnesToTheirSteps) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const float preExposure = 1.0f / s.gpu.desc.typicalRadiance;
  constexpr VkFormat kHalf = VK_FORMAT_R16G16B16A16_SFLOAT, kPacked = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
  for (uint32_t i = 0; i < gi::kMethodCount; ++i) {
    gi::Settings settings;
    settings.method = gi::Method(i);
    const std::string name = gi::methodName(settings.method);
    Stored half, composite, all;
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, kHalf, preExposure, half));
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, kHalf, preExposure, composite, kHalf, kFrames, kPacked));
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, kPacked, preExposure, all));
    EXPECT_TRUE(sameBits(half.direct, composite.direct)) << name;
    EXPECT_TRUE(sameBits(half.indirect, composite.indirect)) << name;
    expectWithinPackedSteps(half.composite, composite.composite, 1.0f / 16.0f, name + " composite alone");
    expectWithinPackedSteps(half.direct, all.direct, 1.0f / 32.0f, name + " direct");
    expectWithinPackedSteps(half.indirect, all.indirect, 1.0f / 32.0f, name + " indirect");
    expectWithinPackedSteps(half.composite, all.composite, 1.0f / 16.0f, name + " composite");
  }
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
  desc.compositeFormat = VK_FORMAT_R8G8B8A8_UNORM;
  gi::Module* m = nullptr;
  const gi::Error e = gi::create(desc, gi::Settings{}, m);
  EXPECT_EQ(e.code, gi::ErrorCode::UnsupportedFormat);
  EXPECT_NE(e.message.find("desc.compositeFormat = R8G8B8A8Unorm"), std::string::npos) << e.message;
  EXPECT_EQ(m, nullptr);
}

// The blended light in half floats (ModuleDesc::historyFormat's default:
// the radiance histories and the noisy indirect, radiance over the scene's
// typical radiance) gives every method the
// image it gives with single-float histories, to half-float rounding carried
// through the frames' blend: 12 frames, single-float outputs.
TEST_F(ModuleOutputsTest, HalfFloatHistoriesMatchSingleFloatOnes) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const float preExposure = 1.0f / s.gpu.desc.typicalRadiance;
  constexpr VkFormat kSingle = VK_FORMAT_R32G32B32A32_SFLOAT, kHalf = VK_FORMAT_R16G16B16A16_SFLOAT;
  for (uint32_t i = 0; i < gi::kMethodCount; ++i) {
    gi::Settings settings;
    settings.method = gi::Method(i);
    Stored half, single;
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, kSingle, preExposure, half, kHalf, 12));
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, kSingle, preExposure, single, kSingle, 12));
    const char* name = gi::methodName(settings.method);
    const double direct = relativeL1(half.direct, single.direct), indirect = relativeL1(half.indirect, single.indirect),
                 composite = relativeL1(half.composite, single.composite);
    std::printf("%-9s half vs single histories, relative L1: direct %.2e, indirect %.2e, composite %.2e\n", name,
                direct, indirect, composite);
    // Measured: at most 6.5e-4 direct, 2.3e-3 indirect (the noisy image and the history
    // each round every frame), 8.7e-4 composite; svgf, whose means ride in the histories' alphas,
    // 9.4e-4, 2.8e-3 and 1.2e-3.
    EXPECT_LT(direct, 2e-3) << name << " direct";
    EXPECT_LT(indirect, 3e-3) << name << " indirect";
    EXPECT_LT(composite, 2e-3) << name << " composite";
  }
}

// A power-of-two pre-exposure scales stored light exactly; pictures (the
// normal view, aaf_ao's occlusion and AO) do not move; gi::outputScales says
// which is which.
TEST_F(ModuleOutputsTest, PreExposureScalesLightAndLeavesPicturesAlone) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  constexpr float kScale = 1.0f / 64.0f;
  struct Case {
    const char* what;
    gi::Method method;
    gi::DebugView view;
  };
  const Case cases[] = {{"raw", gi::Method::Raw, gi::DebugView::None},
                        {"atrous", gi::Method::Atrous, gi::DebugView::None},
                        {"hpsf", gi::Method::Hpsf, gi::DebugView::None},
                        {"raw, normal view", gi::Method::Raw, gi::DebugView::Normal},
                        {"aaf_ao", gi::Method::AafAo, gi::DebugView::None}};
  for (const Case& c : cases) {
    gi::Settings settings;
    settings.method = c.method;
    settings.debugView = c.view;
    Stored plain, scaled;
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f, plain));
    ASSERT_NO_FATAL_FAILURE(renderOutputs(ctx, s, settings, VK_FORMAT_R32G32B32A32_SFLOAT, kScale, scaled));
    const gi::OutputScales expected = gi::outputScales(settings, kScale);
    const std::pair<const engine::FloatImage*, const engine::FloatImage*> images[] = {
        {&plain.direct, &scaled.direct}, {&plain.indirect, &scaled.indirect}, {&plain.composite, &scaled.composite}};
    const float factors[] = {expected.direct, expected.indirect, expected.composite};
    double lit = 0.0;
    for (int k = 0; k < 3; ++k) {
      const engine::FloatImage& a = *images[k].first;
      const engine::FloatImage& b = *images[k].second;
      size_t mismatches = 0;
      for (size_t i = 0; i < a.pixels.size(); ++i) {
        mismatches += b.pixels[i] != a.pixels[i] * factors[k];
        lit += a.pixels[i];
      }
      EXPECT_EQ(mismatches, 0u) << c.what << ", output " << k << ", factor " << factors[k];
    }
    EXPECT_GT(lit, 0.0) << c.what << ": nothing to compare";
  }
  EXPECT_EQ(gi::outputScales(
                [] {
                  gi::Settings x;
                  x.debugView = gi::DebugView::Normal;
                  return x;
                }(),
                kScale)
                .composite,
            1.0f);
}

// Light beyond half float's range is clamped at 65504, never Inf.
TEST_F(ModuleOutputsTest, HalfFloatOutputsClampInsteadOfOverflowing) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Bilateral, gi::Method::Hpsf}) {
    gi::Settings settings;
    settings.method = method;
    Stored out;
    ASSERT_NO_FATAL_FAILURE(
        renderOutputs(ctx, s, settings, VK_FORMAT_R16G16B16A16_SFLOAT, 1e9f / s.gpu.desc.typicalRadiance, out));
    size_t atLimit = 0;
    for (const engine::FloatImage* img : {&out.direct, &out.indirect, &out.composite})
      for (float v : img->pixels) {
        ASSERT_TRUE(std::isfinite(v)) << gi::methodName(method);
        ASSERT_LE(std::fabs(v), 65504.0f) << gi::methodName(method);
        atLimit += v == 65504.0f;
      }
    EXPECT_GT(atLimit, size_t(kSize)) << gi::methodName(method) << ": lit pixels sit at the limit";
  }
}

// A pre-exposure that is not a positive finite factor is a named error and records nothing.
TEST_F(ModuleOutputsTest, BadPreExposureIsANamedError) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, session));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  for (float bad : {0.0f, -1.0f, std::nanf(""), INFINITY}) {
    gi::FrameInputs in;
    in.gbuffer = tools::gbufferViews(session.gbuffer);
    in.camera = in.previousCamera = engine::moduleCamera(cam);
    in.preExposure = bad;
    gi::Error e;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::recordFrame(session.module, cmd, in); });
    EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange) << bad;
    EXPECT_NE(e.message.find("preExposure"), std::string::npos) << e.message;
  }
}
