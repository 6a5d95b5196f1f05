// The raster G-buffer and the ray tracer must agree on what the camera sees:
// same surfaces, same depth, same normals.
#include <cstring>

#include "gbuffer.h"
#include "gpu_test.h"

namespace {

std::vector<float> readFloats(const engine::Context& ctx, const engine::Image& img, size_t texelBytes) {
  std::vector<std::byte> raw = engine::readbackImage(ctx, img, VK_IMAGE_LAYOUT_GENERAL, texelBytes);
  std::vector<float> out(raw.size() / 4);
  std::memcpy(out.data(), raw.data(), raw.size());
  return out;
}

using engine::halfToFloat;

}  // namespace

class GBufferTest : public GpuTest {};

// Raster and ray tracing must agree: same surfaces, depths and normals, also
// after an instance moves and the TLAS is rebuilt (which also yields motion).
TEST_F(GBufferTest, DepthAndNormalMatchRayTracedPrimaryHits) {
  for (const char* scenePath : {"cornell-box-mcguire/CornellBox-Original.gltf", "cornell-simple/cornell_simple.gltf", "moved"}) {
    LoadedScene s;
    bool moved = std::string(scenePath) == "moved";
    load(sharedScene(moved ? "cornell-simple/cornell_simple.gltf" : scenePath), s);
    if (moved) {
      // Move every instance of the shared box mesh 0.2 m along x and rebuild the TLAS.
      uint32_t boxMesh = s.scene.instances.back().mesh;
      for (engine::Instance& inst : s.scene.instances)
        if (inst.mesh == boxMesh) inst.worldFromObject[3] += glm::vec4(0.2f, 0.0f, 0.0f, 0.0f);
      engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) { engine::recordSceneTransformUpdate(ctx, cmd, s.scene, s.gpu); });
    }
    const uint32_t W = 64, H = 48;
    gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], W, H, nullptr);
    engine::GBuffer gbuffer = engine::createGBuffer(ctx, {W, H});
    engine::GBufferPass pass = engine::createGBufferPass(ctx, s.gpu);
    engine::submitAndWait(ctx, [&](VkCommandBuffer cmd) { engine::recordGBuffer(ctx, cmd, pass, s.scene, s.gpu, gbuffer, cam, nullptr); });
    std::vector<float> viewZ = readFloats(ctx, gbuffer.color[gpu::GBUFFER_VIEWZ], 4);
    std::vector<std::byte> normalRaw = engine::readbackImage(ctx, gbuffer.color[gpu::GBUFFER_NORMAL], VK_IMAGE_LAYOUT_GENERAL, 8);

    engine::ReferenceSettings settings;
    settings.pixelJitter = false;
    settings.maxBounces = 0;
    engine::ReferenceImages rt = engine::renderReference(ctx, s.gpu, cam, settings, 1).images;

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
    // Only pixels whose centre sits on an edge may disagree.
    EXPECT_GE(double(agree) / compared, 0.98) << scenePath << ": " << agree << " of " << compared << " pixels agree";
    if (moved) {
      // The moved instances carry motion: some pixels point back to where they were.
      std::vector<std::byte> motion = engine::readbackImage(ctx, gbuffer.color[gpu::GBUFFER_MOTION], VK_IMAGE_LAYOUT_GENERAL, 4);
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
    unload(s);
  }
}
