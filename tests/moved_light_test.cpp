// The light jumps while the camera stays: what the temporal pass keeps of the
// old light. A-SVGF's temporal gradients (temporal.gradients,
// shaders/module/temporal.glsl): with nothing moving, a gradient sample repeats last
// frame's sample bit for bit, so no history is dropped; when the light moves,
// the gradients see it and the accumulated light catches up with the moved
// scene sooner. The history clamp (temporal.historyClamp) holds the
// reprojected history near this frame's samples around the pixel, which also
// lets the old light go sooner.
#include <functional>
#include <string>

#include "animation.h"
#include "metrics.h"
#include "module_test_helpers.h"

namespace {

constexpr uint32_t kSize = 48;
constexpr uint32_t kStill = 24, kAfter = 8;  // frames before the light jumps, and after

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

// kStill frames of the Cornell box as loaded, then the light half a circle away for kAfter frames:
// each later frame's error against a reference of the moved scene, and the gradient view's λ.
struct Jump {
  double direct[kAfter], indirect[kAfter];
  double stillDirect = 0.0;  // the last still frame's direct MSE against a reference of the unmoved scene
  Lambda still, afterMove;   // λ over the still frames (max), in the first frame after the move
};

class LightJump {
 public:
  LightJump(const engine::Context& ctx, LoadedScene& s)
      : ctx_(ctx), s_(s), animation_(engine::makeSceneAnimation(s.scene)) {
    cam_ = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
    pose(0.0f);
    unmoved_ = pixelCentreReference(ctx, s, cam_, 1, 1024);
    pose(0.5f * animation_.periodSeconds);  // the light half a circle away
    moved_ = pixelCentreReference(ctx, s, cam_, 1, 1024);
  }
  bool hasLight() const { return animation_.lightInstance >= 0; }

  // `settings` with the composite showing λ (direct and indirect are the light).
  Jump run(gi::Settings settings) {
    Jump j;
    pose(0.0f);
    settings.debugView = gi::DebugView::TemporalGradient;
    ScopedSession session(ctx_);
    EXPECT_NO_FATAL_FAILURE(openSession(ctx_, s_, {kSize, kSize}, settings, session));
    uint32_t frame = 0;
    for (; frame < kStill; ++frame) {
      tools::renderModuleFrame(ctx_, session, s_.scene, s_.gpu, cam_, cam_, frame);
      const engine::ReferenceImages img = tools::readModuleImages(ctx_, session);
      j.still.max = std::max(j.still.max, lambdaOf(img.final).max);
      if (frame + 1 == kStill) j.stillDirect = metrics::mse(img.direct, unmoved_.direct);
    }
    pose(0.5f * animation_.periodSeconds);
    for (uint32_t k = 0; k < kAfter; ++k, ++frame) {
      tools::renderModuleFrame(ctx_, session, s_.scene, s_.gpu, cam_, cam_, frame);
      const engine::ReferenceImages img = tools::readModuleImages(ctx_, session);
      if (k == 0) j.afterMove = lambdaOf(img.final);
      j.direct[k] = metrics::mse(img.direct, moved_.direct);
      j.indirect[k] = metrics::mse(img.indirect, moved_.indirect);
    }
    tools::destroyModuleSession(ctx_, session);
    return j;
  }

 private:
  void pose(float seconds) { jumpOrFail(ctx_, animation_, seconds, s_.scene, s_.gpu); }  // the light jumps

  const engine::Context& ctx_;
  LoadedScene& s_;
  engine::SceneAnimation animation_;
  gpu::GpuCamera cam_;
  engine::ReferenceImages unmoved_, moved_;
};

void print(const char* what, const Jump& j) {
  std::printf(
      "%s: still max lambda %.3g; first frame after the move mean lambda %.3f; last still frame direct MSE "
      "%.3e; after the move direct MSE after 1/2/4/8 frames %.3e %.3e %.3e %.3e, indirect %.3e %.3e %.3e %.3e\n",
      what, j.still.max, j.afterMove.mean, j.stillDirect, j.direct[0], j.direct[1], j.direct[3], j.direct[7],
      j.indirect[0], j.indirect[1], j.indirect[3], j.indirect[7]);
}

struct OffAndOn {
  Jump off, on;
};

}  // namespace

class MovedLightTest : public GpuTest {
 protected:
  // The same jump without and with one change to the settings (`change`), both printed.
  static OffAndOn offAndOn(gi::Method method, const char* what, const std::function<void(gi::Settings&)>& change) {
    LoadedScene s;
    load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
    LightJump jump(ctx, s);
    EXPECT_TRUE(jump.hasLight());
    gi::Settings settings;
    settings.method = method;
    OffAndOn r;
    r.off = jump.run(settings);
    change(settings);
    r.on = jump.run(settings);
    print((std::string(what) + " off").c_str(), r.off);
    print((std::string(what) + " on ").c_str(), r.on);
    s.release();
    return r;
  }
};

TEST_F(MovedLightTest, GradientsDropNothingWhileStillAndCatchTheMovedLightSooner) {
  const auto [off, on] = offAndOn(gi::Method::Svgf, "gradients", [](gi::Settings& x) { x.temporal.gradients = true; });
  // Nothing moved: every gradient sample repeated last frame's exactly.
  EXPECT_EQ(on.still.max, 0.0);
  EXPECT_EQ(off.afterMove.max, 0.0) << "the view is black with the gradients off";
  // The move: the light changed almost everywhere.
  EXPECT_GT(on.afterMove.mean, 0.3);
  // And the light catches up (measured, 48², 1 spp: direct 0.50× and 0.57× the error without
  // gradients 2 and 4 frames after the move, indirect 0.81× and 0.79×).
  for (uint32_t k : {1u, 3u}) {
    EXPECT_LT(on.direct[k], 0.7 * off.direct[k]) << k + 1 << " frames after the move";
    EXPECT_LT(on.indirect[k], 0.9 * off.indirect[k]) << k + 1 << " frames after the move";
  }
}

// The history clamp at γ_h = 1: the old direct light, far outside what this
// frame's samples around a pixel spread over, is scaled back, so its error
// after the jump falls sooner (measured, 48²: 0.55× and 0.52× of without, 1
// and 2 frames after). The indirect light does not gain (1.3–1.5× the error:
// nine 1-spp indirect samples spread so unevenly that the band cuts good
// history too), and with the light still the clamp costs accuracy (direct
// 1.5× after 24 still frames): why it is off by default (RESULTS, "The
// history clamp").
TEST_F(MovedLightTest, HistoryClampLetsTheOldLightGoSooner) {
  const auto [off, on] =
      offAndOn(gi::Method::Gif, "history clamp", [](gi::Settings& x) { x.temporal.historyClamp = 1.0f; });
  for (uint32_t k : {0u, 1u}) EXPECT_LT(on.direct[k], 0.7 * off.direct[k]) << k + 1 << " frames after the move";
  EXPECT_GT(on.stillDirect, off.stillDirect) << "held near nine samples' band, the still history is noisier";
}
