// The images FrameStats::memoryTransientBytes counts live within one frame:
// every frame writes them before it reads them, so an engine may give their
// memory to anything else between frames (NRD's transient pool). Shown by
// filling each of them with NaN after every frame: every method, frames of a
// moving scene, renders the same bits as without the filling.
#include <algorithm>
#include <cmath>

#include "gi/catalogue.h"
#include "gi/settings.h"
#include "module.h"
#include "module_test_helpers.h"

namespace {

constexpr uint32_t kSize = 32, kFrames = 5;

// The images the next frame writes before it reads them: the frame-lifetime images, and where the frame's
// reservoirs borrow it (gi::reservoirHomes) the history set the next frame's temporal pass overwrites
// (it reads set temporalFrames & 1 and writes the other), which holds the light of the frame before last.
// Not the outputs, which the engine reads between frames.
std::vector<const gi::vk::Image*> imagesTheNextFrameWritesFirst(const gi::Module& m) {
  std::vector<const gi::vk::Image*> images = gi::frameImages(m.sized);
  const gi::ReservoirHomes homes = gi::reservoirHomes(m.sized, m.outputs, (m.temporalFrames & 1u) == 0u ? 1u : 0u);
  for (const gi::vk::Image* home : {homes.set, homes.pick})
    if (home != &m.outputs.direct && home != &m.outputs.composite &&
        std::find(images.begin(), images.end(), home) == images.end())
      images.push_back(home);
  return images;
}

// Those images filled with NaN.
void fillFrameImagesWithNan(const engine::Context& ctx, const gi::Module& m) {
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearColorValue nan{{std::nanf(""), std::nanf(""), std::nanf(""), std::nanf("")}};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (const gi::vk::Image* image : imagesTheNextFrameWritesFirst(m))
      vkCmdClearColorImage(cmd, image->image, VK_IMAGE_LAYOUT_GENERAL, &nan, 1, &range);
    engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  });
}

}  // namespace

class ModuleLifetimeTest : public GpuTest {};

TEST_F(ModuleLifetimeTest, FrameImagesCanBeOverwrittenBetweenFramesInEveryMethod) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  for (const gi::MethodInfo& info : gi::methodCatalogue()) {
    gi::Settings settings;
    settings.method = info.method;
    // The hash methods' frames reproduce only on a still scene (robust_access_test.cpp says why).
    const bool moving = !gi::usesHashGrid(info.method);
    const engine::ReferenceImages kept = renderAnimatedFrames(ctx, s, animation, settings, kSize, kFrames, moving);
    const engine::ReferenceImages filled =
        renderAnimatedFrames(ctx, s, animation, settings, kSize, kFrames, moving,
                             [&](tools::ModuleSession& session) { fillFrameImagesWithNan(ctx, *session.module); });
    ASSERT_FALSE(kept.final.pixels.empty()) << info.name;
    EXPECT_TRUE(sameBits(kept.direct, filled.direct)) << info.name << ": direct read a frame image's last contents";
    EXPECT_TRUE(sameBits(kept.indirect, filled.indirect))
        << info.name << ": indirect read a frame image's last contents";
    EXPECT_TRUE(sameBits(kept.final, filled.final)) << info.name << ": composite read a frame image's last contents";
  }
}

// The reservoirs (the Cornell box's ceiling light resampled: reservoirs.emissive_min = 0): raw, which has no
// temporal pass, merges last frame's reservoirs, so both sets are history; svgf and hpsf keep one set, which
// the temporal reservoir pass writes and the spatial one reads within the frame (neither A nor B held):
// svgf in the history set its temporal pass overwrites later in the frame, as does the pick; hpsf, whose
// direct history is one packed image, in the direct output, and the pick in the composite (no image of
// their own held by either), where raw's pick lives too. Filled with NaN after every frame (svgf: that history set too), the same bits;
// the outputs, which the engine reads, are shown apart (ReservoirsInTheOutputs…).
TEST_F(ModuleLifetimeTest, ReservoirsWithoutTheirMergeLiveWithinTheFrame) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Svgf, gi::Method::Hpsf}) {
    SCOPED_TRACE(gi::methodName(method));
    gi::Settings settings;
    settings.method = method;
    settings.reservoirs.emissiveMin = 0;
    const bool moving = !gi::usesHashGrid(method);
    bool resampled = false, setListed = false, setsHeld = false, pickListed = false, borrowed = false,
         inOutputs = false;
    const engine::ReferenceImages kept =
        renderAnimatedFrames(ctx, s, animation, settings, kSize, kFrames, moving, [&](tools::ModuleSession& session) {
          const gi::Module& m = *session.module;
          const std::vector<const gi::vk::Image*> images = gi::frameImages(m.sized);
          resampled = m.plan.reservoirs;
          // Images a plan does not need are 1×1 placeholders.
          setListed = std::find(images.begin(), images.end(), &m.sized.frameReservoirs) != images.end() &&
                      m.sized.frameReservoirs.extent.width == kSize;
          setsHeld = m.sized.reservoirsA.extent.width == kSize && m.sized.reservoirsB.extent.width == kSize;
          pickListed = std::find(images.begin(), images.end(), &m.sized.reservoirPick) != images.end() &&
                       m.sized.reservoirPick.extent.width == kSize;
          const gi::ReservoirHomes homes = gi::reservoirHomes(m.sized, m.outputs, 0);
          borrowed = homes.set == &m.sized.historyDirectA && homes.pick == &m.sized.historyIndirectA &&
                     m.sized.historyDirectA.alsoView != VK_NULL_HANDLE;
          // Where the sets are merged the frame's set is unused (its 1×1 placeholder).
          inOutputs = (homes.set == &m.outputs.direct || setsHeld) && homes.pick == &m.outputs.composite &&
                      m.outputs.direct.alsoView != VK_NULL_HANDLE && m.outputs.composite.alsoView != VK_NULL_HANDLE;
        });
    const engine::ReferenceImages filled =
        renderAnimatedFrames(ctx, s, animation, settings, kSize, kFrames, moving,
                             [&](tools::ModuleSession& session) { fillFrameImagesWithNan(ctx, *session.module); });
    ASSERT_TRUE(resampled) << "the reservoirs run";
    EXPECT_FALSE(setListed) << "no set of its own within the frame";
    EXPECT_EQ(setsHeld, method == gi::Method::Raw) << "the two sets of history only where they are merged";
    EXPECT_FALSE(pickListed) << "no pick of its own";
    EXPECT_EQ(borrowed, method == gi::Method::Svgf) << "the set and the pick in the history set to be overwritten";
    EXPECT_EQ(inOutputs, method != gi::Method::Svgf) << "the set and the pick (raw: the pick) in the outputs";
    EXPECT_TRUE(sameBits(kept.direct, filled.direct)) << "direct read a frame image's last contents";
    EXPECT_TRUE(sameBits(kept.indirect, filled.indirect)) << "indirect read a frame image's last contents";
    EXPECT_TRUE(sameBits(kept.final, filled.final)) << "composite read a frame image's last contents";
  }
}

// The reservoirs and pick in the direct output and the composite where no history set lends them (the
// hash methods' one packed history; svgf's with single-float histories), and the pick alone where the
// sets are merged (raw, AAF): the direct and indirect outputs are the same bits as where the composite
// cannot lend (single floats: sixteen bytes a texel), where the set and the pick are images of their own. A pass that read the direct output or the composite
// before writing it, or wrote them while the set or the pick was still to be read, would tell them apart.
TEST_F(ModuleLifetimeTest, ReservoirsInTheOutputsGiveTheSameLightAsImagesOfTheirOwn) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  gi::ModuleDesc lending = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
  lending.historyFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // svgf has no half-float set to lend then
  gi::ModuleDesc ownImages = lending;
  ownImages.compositeFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
  for (gi::Method method : {gi::Method::Hpsf, gi::Method::Anhpsf, gi::Method::Svgf, gi::Method::Raw, gi::Method::Aaf}) {
    SCOPED_TRACE(gi::methodName(method));
    gi::Settings settings;
    settings.method = method;
    settings.reservoirs.emissiveMin = 0;
    bool lent = false, own = false;
    const engine::ReferenceImages inOutputs = renderAnimatedFrames(
        ctx, s, animation, settings, kSize, kFrames, false,
        [&](tools::ModuleSession& session) {
          const gi::Module& m = *session.module;
          const gi::ReservoirHomes homes = gi::reservoirHomes(m.sized, m.outputs, 0);
          const bool merged = m.sized.reservoirsA.extent.width == kSize;
          lent = homes.pick == &m.outputs.composite && (merged || homes.set == &m.outputs.direct);
        },
        &lending);
    const engine::ReferenceImages apart = renderAnimatedFrames(
        ctx, s, animation, settings, kSize, kFrames, false,
        [&](tools::ModuleSession& session) {
          const gi::SizedResources& r = session.module->sized;
          const gi::ReservoirHomes homes = gi::reservoirHomes(r, session.module->outputs, 0);
          const bool merged = r.reservoirsA.extent.width == kSize;
          own = homes.set == &r.frameReservoirs && homes.pick == &r.reservoirPick &&
                (merged || r.frameReservoirs.extent.width == kSize) && r.reservoirPick.extent.width == kSize;
        },
        &ownImages);
    ASSERT_FALSE(inOutputs.final.pixels.empty());
    EXPECT_TRUE(lent) << "the outputs hold the set and the pick";
    EXPECT_TRUE(own) << "single-float composite: images of their own";
    EXPECT_TRUE(sameBits(inOutputs.direct, apart.direct)) << "direct";
    EXPECT_TRUE(sameBits(inOutputs.indirect, apart.indirect)) << "indirect";
  }
}

// With packed outputs (B10G11R11) the passes' direct and indirect light is the module's own half-float
// pair, listed as frame images with the rest: filled with NaN after every frame, the methods that use the
// outputs as scratch (svgf's à-trous, the hash methods' samples, à-trous's ping-pong) and raw render the
// same bits.
TEST_F(ModuleLifetimeTest, PackedOutputsWorkingImagesCanBeOverwrittenBetweenFrames) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
  desc.outputFormat = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
  for (gi::Method method : {gi::Method::Raw, gi::Method::Atrous, gi::Method::Svgf, gi::Method::Hpsf}) {
    gi::Settings settings;
    settings.method = method;
    const char* name = gi::methodName(method);
    const bool moving = !gi::usesHashGrid(method);
    size_t listed = 0;
    const engine::ReferenceImages kept =
        renderAnimatedFrames(ctx, s, animation, settings, kSize, kFrames, moving, {}, &desc);
    const engine::ReferenceImages filled = renderAnimatedFrames(
        ctx, s, animation, settings, kSize, kFrames, moving,
        [&](tools::ModuleSession& session) {
          const gi::SizedResources& r = session.module->sized;
          for (const gi::vk::Image* image : gi::frameImages(r))
            listed += image == &r.workDirect || image == &r.workIndirect;
          fillFrameImagesWithNan(ctx, *session.module);
        },
        &desc);
    EXPECT_EQ(listed, 2u * kFrames) << name << ": the working pair is among the frame images";
    ASSERT_FALSE(kept.final.pixels.empty()) << name;
    EXPECT_TRUE(sameBits(kept.direct, filled.direct)) << name;
    EXPECT_TRUE(sameBits(kept.indirect, filled.indirect)) << name;
    EXPECT_TRUE(sameBits(kept.final, filled.final)) << name;
  }
}

// What the stats call transient is what the list holds, and part of what the
// screen filters hold is transient (their guidance, positions where they read
// them and, for gif, the window statistics); the histories are not.
TEST_F(ModuleLifetimeTest, TransientBytesAreTheFrameImages) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 64, 64, nullptr);
  for (gi::Method method : {gi::Method::Raw, gi::Method::Gif, gi::Method::Hpsf}) {
    gi::Settings settings;
    settings.method = method;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {64, 64}, settings, session));
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    const gi::FrameStats st = gi::stats(session.module);
    uint64_t listed = 0;
    for (const gi::vk::Image* image : gi::frameImages(session.module->sized)) listed += image->memory.size;
    EXPECT_EQ(st.memoryTransientBytes, listed) << gi::methodName(method);
    EXPECT_LT(st.memoryTransientBytes, st.memoryUsedBytes) << gi::methodName(method);
    const uint64_t image = 64 * 64 * 16;  // one rgba32f image
    if (method == gi::Method::Gif) {      // the 8 statistics images (1/s² of the size) and the guidance
      const uint64_t per = uint64_t(settings.gif.subsample) * settings.gif.subsample;       // pixels a statistics pixel
      EXPECT_GE(st.memoryTransientBytes, FILTER_STACK * image / per + image / 2) << "gif";  // (half floats)
    }
    if (method == gi::Method::Hpsf) {  // the sample goes into the output; the direct history persists
      EXPECT_LT(st.memoryTransientBytes, image) << "hpsf";
    }
  }
}

// The screen filters with temporal reprojection trace their noisy indirect into the indirect output and
// filter the indirect history the temporal pass wrote (MethodPlan::filtersReadHistory): no noisy image of
// their own. With the filter in | out view, which shows the noisy image beside the output, they hold one
// again and the temporal pass hands them its result there. Frames of a moving scene: the direct output's
// bits and the indirect output within the half floats' rounding are the same either way, so the filters
// read this frame's history set (not last frame's), and nothing (the temporal pass, the filter clamp's
// spread and filter-vertex flag) reads the traced light from the output once a filter has written it.
TEST_F(ModuleLifetimeTest, ScreenFiltersTraceIntoTheIndirectOutputAndFilterTheSameLight) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  for (gi::Method method : {gi::Method::Gif, gi::Method::Bilateral, gi::Method::Atrous, gi::Method::Sspsf}) {
    const char* name = gi::methodName(method);
    gi::Settings aliased;
    aliased.method = method;
    gi::Settings apart = aliased;
    apart.debugView = gi::DebugView::FilterInOut;
    bool aliasedHeldNoisy = true, apartHeldNoisy = false;
    const engine::ReferenceImages one = renderAnimatedFrames(
        ctx, s, animation, aliased, kSize, kFrames, true,
        [&](tools::ModuleSession& session) { aliasedHeldNoisy = !gi::noisyAliasesIndirect(session.module->sized); });
    const engine::ReferenceImages two = renderAnimatedFrames(
        ctx, s, animation, apart, kSize, kFrames, true,
        [&](tools::ModuleSession& session) { apartHeldNoisy = !gi::noisyAliasesIndirect(session.module->sized); });
    EXPECT_FALSE(aliasedHeldNoisy) << name << ": the noisy indirect is traced into the indirect output";
    EXPECT_TRUE(apartHeldNoisy) << name << ": the filter in | out view keeps a noisy image";
    ASSERT_FALSE(one.indirect.pixels.empty()) << name;
    EXPECT_TRUE(sameBits(one.direct, two.direct)) << name;
    ASSERT_EQ(one.indirect.pixels.size(), two.indirect.pixels.size()) << name;
    // The traced light is rounded to half floats in the output's units (× pre-exposure) instead of the
    // noisy image's (÷ the scene's typical radiance): a pixel may move by a few half-float steps (2^-11
    // of its value each), where the wrong history set or the filter's own output read back would move
    // it by the light's change between frames.
    float worst = 0.0f;
    for (size_t i = 0; i < one.indirect.pixels.size(); ++i) {
      const float a = one.indirect.pixels[i], b = two.indirect.pixels[i];
      worst = std::max(worst, std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-6f}));
    }
    EXPECT_LE(worst, 1.0f / 256.0f) << name << ": the filtered light depends on where the trace went";
  }
}
