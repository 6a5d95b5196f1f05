// The raster G-buffer and the ray tracer must agree on what the camera sees:
// same surfaces, same depth, same normals.
#include <cstring>

#include "gbuffer.h"
#include "gpu_test.h"

namespace {

std::vector<float> readFloats(const engine::Context& ctx, const engine::Image& img, size_t texelBytes) {
  std::vector<std::byte> raw = readbackOrFail(ctx, img, VK_IMAGE_LAYOUT_GENERAL, texelBytes);
  std::vector<float> out(raw.size() / 4);
  std::memcpy(out.data(), raw.data(), raw.size());
  return out;
}

using engine::halfToFloat;

}  // namespace

class GBufferTest : public GpuTest {
 protected:
  // The share of pixels where the raster G-buffer and ray-traced primary hits
  // through giCameraRayDirection agree: both background, or the same depth
  // (0.1%) and normal (cos > 0.999).
  double rasterAgreesWithRays(const LoadedScene& s, const engine::GBuffer& gbuffer, const gpu::GpuCamera& cam) {
    const uint32_t W = gbuffer.extent.width, H = gbuffer.extent.height;
    std::vector<float> viewZ = readFloats(ctx, gbuffer.color[gpu::GBUFFER_VIEWZ], 4);
    std::vector<std::byte> normalRaw =
        readbackOrFail(ctx, gbuffer.color[gpu::GBUFFER_NORMAL], VK_IMAGE_LAYOUT_GENERAL, 8);

    engine::ReferenceSettings settings;
    settings.pixelJitter = false;
    settings.maxBounces = 0;
    engine::ReferenceImages rt = referenceOrFail(ctx, s.gpu, cam, settings, 1, 4).images;

    uint32_t compared = 0, agree = 0;
    for (uint32_t y = 0; y < H; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        size_t i = size_t(y) * W + x;
        uint16_t h[4];
        std::memcpy(h, &normalRaw[i * 8], 8);
        glm::vec3 rasterNormal(halfToFloat(h[0]), halfToFloat(h[1]), halfToFloat(h[2]));
        float rasterZ = viewZ[i], rtZ = rt.depth.at(x, y, 0);
        bool rasterHit = halfToFloat(h[3]) > 0.5f, rtHit = rtZ > 0.0f;
        ++compared;
        if (rasterHit != rtHit) continue;  // a silhouette pixel: the two may differ by one sample position
        if (!rasterHit) {
          ++agree;
          continue;
        }
        glm::vec3 rtNormal(rt.normal.at(x, y, 0), rt.normal.at(x, y, 1), rt.normal.at(x, y, 2));
        bool depthOk = std::abs(rasterZ - rtZ) <= 1e-3f * rtZ;
        bool normalOk = glm::dot(rasterNormal, rtNormal) > 0.999f;
        if (depthOk && normalOk) ++agree;
      }
    return double(agree) / compared;
  }
};

// Raster and ray tracing must agree: same surfaces, depths and normals, also
// after an instance moves and the TLAS is rebuilt (which also yields motion).
TEST_F(GBufferTest, DepthAndNormalMatchRayTracedPrimaryHits) {
  for (const char* scenePath :
       {"cornell-box-mcguire/CornellBox-Original.gltf", "cornell-simple/cornell_simple.gltf", "moved"}) {
    LoadedScene s;
    bool moved = std::string(scenePath) == "moved";
    load(sharedScene(moved ? "cornell-simple/cornell_simple.gltf" : scenePath), s);
    if (moved) {
      // Move every instance of the shared box mesh 0.2 m along x and rebuild the TLAS.
      uint32_t boxMesh = s.scene.instances.back().mesh;
      for (engine::Instance& inst : s.scene.instances)
        if (inst.mesh == boxMesh) inst.worldFromObject[3] += glm::vec4(0.2f, 0.0f, 0.0f, 0.0f);
      submitOrFail(ctx, [&](VkCommandBuffer cmd) { recordUpdateOrFail(ctx, cmd, s.scene, s.gpu); });
    }
    const uint32_t W = 64, H = 48;
    gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
    std::string error;
    engine::GBuffer gbuffer = engine::createGBuffer(ctx, {W, H}, error);
    engine::GBufferPass pass = engine::createGBufferPass(ctx, s.gpu, error);
    ASSERT_EQ(error, "");
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      engine::recordGBuffer(ctx, cmd, pass, s.scene, s.gpu, gbuffer, cam, nullptr);
    });
    const double agreement = rasterAgreesWithRays(s, gbuffer, cam);
    // Only pixels whose centre sits on an edge may disagree.
    EXPECT_GE(agreement, 0.98) << scenePath;
    if (moved) {
      // The moved instances carry motion: some pixels point back to where they were.
      std::vector<std::byte> motion =
          readbackOrFail(ctx, gbuffer.color[gpu::GBUFFER_MOTION], VK_IMAGE_LAYOUT_GENERAL, 4);
      uint32_t moving = 0;
      for (size_t i = 0; i < size_t(W) * H; ++i) {
        uint16_t h[2];
        std::memcpy(h, &motion[4 * i], 4);
        moving += std::abs(halfToFloat(h[0])) > 0.5f;
      }
      EXPECT_GT(moving, 20u);
    }
    engine::destroyGBufferPass(ctx, pass);
    engine::destroyGBuffer(ctx, gbuffer);
  }
}

// TAA jitter and off-axis projections: primary rays come from the
// projection's inverse, so they still go where the raster's samples did.
TEST_F(GBufferTest, JitteredAndOffAxisProjectionsMatchRayTracedPrimaryHits) {
  LoadedScene s;
  load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s);
  const uint32_t W = 64, H = 48;
  std::string error;
  engine::GBuffer gbuffer = engine::createGBuffer(ctx, {W, H}, error);
  engine::GBufferPass pass = engine::createGBufferPass(ctx, s.gpu, error);
  ASSERT_EQ(error, "");
  auto depthOf = [&](const gpu::GpuCamera& cam) {
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      engine::recordGBuffer(ctx, cmd, pass, s.scene, s.gpu, gbuffer, cam, nullptr);
    });
    return readFloats(ctx, gbuffer.color[gpu::GBUFFER_VIEWZ], 4);
  };
  const std::vector<float> centred = depthOf(engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr));
  const glm::vec2 shifts[] = {{2.0f * 0.37f / W, -2.0f * 0.29f / H},  // a sub-pixel jitter
                              {0.3f, -0.2f}};                         // an off-axis projection
  for (glm::vec2 shift : shifts) {
    gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr, shift);
    const std::vector<float> shifted = depthOf(cam);
    uint32_t moved = 0;
    for (size_t i = 0; i < shifted.size(); ++i)
      moved += std::abs(shifted[i] - centred[i]) > 1e-4f * std::max(centred[i], 1.0f);
    EXPECT_GT(moved, 20u) << "the shift moves the image";
    EXPECT_GE(rasterAgreesWithRays(s, gbuffer, cam), 0.98) << "shift " << shift.x << ", " << shift.y;
  }
  engine::destroyGBufferPass(ctx, pass);
  engine::destroyGBuffer(ctx, gbuffer);
}
