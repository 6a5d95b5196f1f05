// A-SVGF's temporal gradients (temporal.gradients, shaders/temporal.glsl):
// with nothing moving, a gradient sample repeats last frame's sample bit for
// bit, so no history is dropped; when the light moves, the gradients see it
// and the accumulated light catches up with the moved scene sooner.
#include "animation.h"
#include "metrics.h"
#include "module_test_helpers.h"

class TemporalGradientTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 48;

// The temporal gradient view: λ of direct (r) and indirect (g) per pixel.
struct Lambda {
  double mean = 0.0, max = 0.0;
};
Lambda lambdaOf(const engine::FloatImage& view) {
  Lambda l;
  const size_t pixels = size_t(view.width) * view.height;
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 2; ++c) {
      l.mean += view.pixels[3 * p + c] / double(2 * pixels);
      l.max = std::max(l.max, double(view.pixels[3 * p + c]));
    }
  return l;
}

}  // namespace

TEST_F(TemporalGradientTest, StillFramesDropNothingAndAMovedLightIsCaughtSooner) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  engine::SceneAnimation animation = engine::makeSceneAnimation(s.scene);
  ASSERT_GE(animation.lightInstance, 0);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  auto pose = [&](float seconds) { engine::jumpScene(ctx, animation, seconds, s.scene, s.gpu); };  // the light jumps
  pose(0.5f * animation.periodSeconds);  // the light half a circle away
  const engine::ReferenceImages moved = pixelCentreReference(ctx, s, cam, 1, 1024);
  constexpr uint32_t kStill = 24, kAfter = 8;
  double direct[2][kAfter], indirect[2][kAfter];
  Lambda still[2], afterMove[2];
  for (int on = 0; on < 2; ++on) {
    pose(0.0f);
    gi::Settings settings;
    settings.method = gi::Method::Svgf;
    settings.temporal.gradients = on == 1;
    settings.debugView = gi::DebugView::TemporalGradient;  // the composite shows λ; direct and indirect are the light
    tools::ModuleSession session;
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, settings, session));
    uint32_t frame = 0;
    for (; frame < kStill; ++frame) {
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
      const Lambda l = lambdaOf(tools::readModuleImages(ctx, session).final);
      still[on].max = std::max(still[on].max, l.max);
    }
    pose(0.5f * animation.periodSeconds);
    for (uint32_t k = 0; k < kAfter; ++k, ++frame) {
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, frame);
      const engine::ReferenceImages img = tools::readModuleImages(ctx, session);
      if (k == 0) afterMove[on] = lambdaOf(img.final);
      direct[on][k] = metrics::mse(img.direct, moved.direct);
      indirect[on][k] = metrics::mse(img.indirect, moved.indirect);
    }
    tools::destroyModuleSession(ctx, session);
  }
  for (int on = 0; on < 2; ++on)
    std::printf("gradients %s: still max lambda %.3g; first frame after the move mean lambda %.3f; direct MSE after "
                "1/2/4/8 frames %.3e %.3e %.3e %.3e, indirect %.3e %.3e %.3e %.3e\n",
                on ? "on " : "off", still[on].max, afterMove[on].mean, direct[on][0], direct[on][1], direct[on][3],
                direct[on][7], indirect[on][0], indirect[on][1], indirect[on][3], indirect[on][7]);
  // Nothing moved: every gradient sample repeated last frame's exactly.
  EXPECT_EQ(still[1].max, 0.0);
  EXPECT_EQ(afterMove[0].max, 0.0) << "the view is black with the gradients off";
  // The move: the light changed almost everywhere.
  EXPECT_GT(afterMove[1].mean, 0.3);
  // And the light catches up (measured, 48², 1 spp: direct 0.50× and 0.57× the error without
  // gradients 2 and 4 frames after the move, indirect 0.81× and 0.79×).
  for (uint32_t k : {1u, 3u}) {
    EXPECT_LT(direct[1][k], 0.7 * direct[0][k]) << k + 1 << " frames after the move";
    EXPECT_LT(indirect[1][k], 0.9 * indirect[0][k]) << k + 1 << " frames after the move";
  }
  unload(s);
}
