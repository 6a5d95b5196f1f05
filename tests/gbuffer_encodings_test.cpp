// The G-buffer adapter (gi::GBufferDesc): the module reads an engine's
// G-buffer in the engine's own formats and encodings. Our G-buffer is
// re-encoded on the CPU into each accepted encoding (octahedral RG16 normals,
// RGB10A2 normals, sRGB albedo, hardware depth with forward and reversed Z,
// motion in UV) and every one gives the image our own encoding gives.
#include <cmath>
#include <cstring>
#include <functional>
#include <glm/gtc/packing.hpp>

#include "frame_slots.h"
#include "metrics.h"
#include "module_test_helpers.h"
#include "readback.h"

class GBufferEncodingsTest : public GpuTest {};

namespace {

constexpr uint32_t kSize = 48;

// Our G-buffer, read back as floats.
struct CpuGBuffer {
  std::vector<glm::vec4> normal, albedo, material, emission;
  std::vector<glm::vec2> motion;
  std::vector<float> viewZ;
};

CpuGBuffer readGBuffer(const engine::Context& ctx, const engine::GBuffer& g) {
  const size_t n = size_t(kSize) * kSize;
  CpuGBuffer c;
  auto halves = [&](uint32_t index, uint32_t channels) {
    std::vector<std::byte> raw = readbackOrFail(ctx, g.color[index], VK_IMAGE_LAYOUT_GENERAL, 2 * channels);
    std::vector<float> out(n * channels);
    for (size_t i = 0; i < out.size(); ++i) {
      uint16_t h;
      std::memcpy(&h, &raw[2 * i], 2);
      out[i] = engine::halfToFloat(h);
    }
    return out;
  };
  std::vector<float> normal = halves(gpu::GBUFFER_NORMAL, 4), motion = halves(gpu::GBUFFER_MOTION, 2);
  std::vector<std::byte> albedo = readbackOrFail(ctx, g.color[gpu::GBUFFER_ALBEDO], VK_IMAGE_LAYOUT_GENERAL, 4);
  std::vector<std::byte> material = readbackOrFail(ctx, g.color[gpu::GBUFFER_MATERIAL], VK_IMAGE_LAYOUT_GENERAL, 2);
  std::vector<std::byte> emission = readbackOrFail(ctx, g.color[gpu::GBUFFER_EMISSION], VK_IMAGE_LAYOUT_GENERAL, 16);
  std::vector<std::byte> viewZ = readbackOrFail(ctx, g.color[gpu::GBUFFER_VIEWZ], VK_IMAGE_LAYOUT_GENERAL, 4);
  for (size_t p = 0; p < n; ++p) {
    c.normal.push_back({normal[4 * p], normal[4 * p + 1], normal[4 * p + 2], normal[4 * p + 3]});
    glm::vec4 a;
    for (int k = 0; k < 4; ++k) a[k] = float(uint8_t(albedo[4 * p + k])) / 255.0f;
    c.albedo.push_back(a);
    c.material.push_back(
        {float(uint8_t(material[2 * p])) / 255.0f, float(uint8_t(material[2 * p + 1])) / 255.0f, 0, 0});
    glm::vec4 e;
    std::memcpy(&e, &emission[16 * p], 16);
    c.emission.push_back(e);
    c.motion.push_back({motion[2 * p], motion[2 * p + 1]});
    float z;
    std::memcpy(&z, &viewZ[4 * p], 4);
    c.viewZ.push_back(z);
  }
  return c;
}

glm::vec2 octahedralEncode(glm::vec3 n) {  // → [-1,1]²
  n /= std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  glm::vec2 e(n.x, n.y);
  if (n.z < 0.0f)
    e = (1.0f - glm::abs(glm::vec2(n.y, n.x))) * glm::vec2(e.x >= 0.0f ? 1.0f : -1.0f, e.y >= 0.0f ? 1.0f : -1.0f);
  return e;
}

uint8_t srgbByte(float linear) { return uint8_t(std::lround(engine::linearToSrgb(linear) * 255.0f)); }

// One image of the encoded G-buffer: its format and texels.
struct Encoded {
  VkFormat format;
  std::vector<uint8_t> bytes;
};
template <typename T>
void put(std::vector<uint8_t>& out, T value) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(&out[at], &value, sizeof(T));
}

// The six images of an encoding, uploaded for the module to sample.
struct UploadedGBuffer {
  engine::Image images[6];
  gi::GBufferViews views() const {
    return {images[0].view, images[1].view, images[2].view, images[3].view, images[4].view, images[5].view};
  }
};

UploadedGBuffer upload(const engine::Context& ctx, const Encoded (&encoded)[6],
                       VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL) {
  UploadedGBuffer u;
  std::string error;
  for (int i = 0; i < 6; ++i) {
    u.images[i] = engine::createImage(ctx, {kSize, kSize}, encoded[i].format,
                                      VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, error);
    engine::uploadImage(ctx, u.images[i], encoded[i].bytes.data(), encoded[i].bytes.size(), layout, error);
  }
  if (!error.empty()) ADD_FAILURE() << error;
  return u;
}

// Our G-buffer as it is, its motion (pixels) turned into motion·motionScale + motionOffset.
void encodeOurs(const CpuGBuffer& g, Encoded (&e)[6], glm::vec2 motionScale = glm::vec2(1.0f),
                glm::vec2 motionOffset = glm::vec2(0.0f)) {
  e[0].format = VK_FORMAT_R16G16B16A16_SFLOAT;
  e[1].format = VK_FORMAT_R8G8B8A8_UNORM;
  e[2].format = VK_FORMAT_R8G8_UNORM;
  e[3].format = VK_FORMAT_R32G32B32A32_SFLOAT;
  e[4].format = VK_FORMAT_R16G16_SFLOAT;
  e[5].format = VK_FORMAT_R32_SFLOAT;
  for (Encoded& image : e) image.bytes.clear();
  for (size_t p = 0; p < g.viewZ.size(); ++p) {
    for (int k = 0; k < 4; ++k) put(e[0].bytes, glm::packHalf1x16(g.normal[p][k]));
    for (int k = 0; k < 4; ++k) put(e[1].bytes, uint8_t(std::lround(g.albedo[p][k] * 255.0f)));
    for (int k = 0; k < 2; ++k) put(e[2].bytes, uint8_t(std::lround(g.material[p][k] * 255.0f)));
    put(e[3].bytes, g.emission[p]);
    for (int k = 0; k < 2; ++k) put(e[4].bytes, glm::packHalf1x16(g.motion[p][k] * motionScale[k] + motionOffset[k]));
    put(e[5].bytes, g.viewZ[p]);
  }
}

// The reversed-Z projection our engine uses, and the same frustum with forward Z.
glm::mat4 clipFromView(const gpu::GpuCamera& cam) { return cam.clipFromWorld * cam.worldFromView; }

struct Variant {
  const char* what;
  gi::GBufferDesc desc;
  std::function<void(const CpuGBuffer&, const glm::mat4& clipFromView, Encoded (&)[6])> encode;
  bool forwardZ = false;  // the camera's projection maps near to 0 and far to 1
  bool yUp = false;       // the projection is handed over y up (an engine drawing with a negative-height viewport)
};

}  // namespace

TEST_F(GBufferEncodingsTest, EveryAcceptedEncodingGivesTheSameImage) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-simple/cornell_simple.gltf"), s));
  const gpu::GpuCamera reversed = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  // Forward Z with the same x and y rows: near → 0, far (or infinity) → 1.
  gpu::GpuCamera forward = reversed;
  {
    glm::mat4 p = clipFromView(reversed);
    const float n = s.scene.cameras[0].znear;
    p[2][2] = -1.0f;  // infinite far plane: d = 1 − n / viewDepth
    p[3][2] = -n;
    forward.clipFromWorld = p * reversed.viewFromWorld;
    forward.previousClipFromWorld = forward.clipFromWorld;
  }

  // Our own G-buffer, rendered once.
  ScopedSession native(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, native));
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    engine::recordGBuffer(ctx, cmd, native.gbufferPass, s.scene, s.gpu, native.gbuffer, reversed, nullptr);
  });
  const CpuGBuffer g = readGBuffer(ctx, native.gbuffer);
  const size_t n = size_t(kSize) * kSize;

  // Each encoding writes the images in their order: normal, albedo, material, emission, motion, depth.
  auto ours = [&](Encoded(&e)[6]) { encodeOurs(g, e); };
  auto hardwareDepth = [&](Encoded& e, const glm::mat4& proj, bool reversedZ) {
    e.format = VK_FORMAT_D32_SFLOAT;
    e.bytes.clear();
    for (size_t p = 0; p < n; ++p) {
      const float z = g.viewZ[p];
      // d = (P22·z_view + P32) / −z_view with z_view = −viewDepth.
      put(e.bytes, z > 0.0f ? (proj[2][2] * -z + proj[3][2]) / z : (reversedZ ? 0.0f : 1.0f));
    }
  };

  std::vector<Variant> variants;
  variants.push_back(
      {"ours", engine::moduleGBufferDesc(), [&](const CpuGBuffer&, const glm::mat4&, Encoded(&e)[6]) { ours(e); }});
  for (bool isSigned : {false, true}) {
    Variant v{isSigned ? "octahedral RG16 snorm normals" : "octahedral RG16 unorm normals", {}, nullptr};
    v.desc.normalFormat = isSigned ? VK_FORMAT_R16G16_SNORM : VK_FORMAT_R16G16_UNORM;
    v.desc.normalEncoding = isSigned ? gi::NormalEncoding::OctahedralSigned : gi::NormalEncoding::Octahedral;
    v.encode = [&, isSigned, format = v.desc.normalFormat](const CpuGBuffer& c, const glm::mat4&, Encoded(&e)[6]) {
      ours(e);
      e[0] = {format, {}};
      for (size_t p = 0; p < n; ++p) {
        glm::vec2 o = c.normal[p].w > 0.5f ? octahedralEncode(glm::vec3(c.normal[p])) : glm::vec2(0.0f);
        for (int k = 0; k < 2; ++k) {
          if (isSigned)
            put(e[0].bytes, int16_t(std::lround(o[k] * 32767.0f)));
          else
            put(e[0].bytes, uint16_t(std::lround((o[k] * 0.5f + 0.5f) * 65535.0f)));
        }
      }
    };
    variants.push_back(v);
  }
  {
    Variant v{"RGB10A2 normals", {}, nullptr};
    v.desc.normalFormat = VK_FORMAT_A2B10G10R10_UNORM_PACK32;
    v.desc.normalEncoding = gi::NormalEncoding::XyzUnorm;
    v.encode = [&](const CpuGBuffer& c, const glm::mat4&, Encoded(&e)[6]) {
      ours(e);
      e[0] = {VK_FORMAT_A2B10G10R10_UNORM_PACK32, {}};
      for (size_t p = 0; p < n; ++p) {
        uint32_t packed = 3u << 30;
        for (int k = 0; k < 3; ++k)
          packed |= uint32_t(std::lround((c.normal[p][k] * 0.5f + 0.5f) * 1023.0f)) << (10 * k);
        put(e[0].bytes, packed);
      }
    };
    variants.push_back(v);
  }
  {
    // The default glossy rule reads the material image: a host that stores opacity in albedo alpha and
    // sets nothing gets the image of our flag.
    Variant v{"sRGB albedo with opacity in alpha, the default glossy rule", {}, nullptr};
    v.desc.albedoFormat = VK_FORMAT_R8G8B8A8_SRGB;
    v.encode = [&](const CpuGBuffer& c, const glm::mat4&, Encoded(&e)[6]) {
      ours(e);
      e[1] = {VK_FORMAT_R8G8B8A8_SRGB, {}};
      for (size_t p = 0; p < n; ++p) {
        for (int k = 0; k < 3; ++k) put(e[1].bytes, srgbByte(c.albedo[p][k]));
        put(e[1].bytes, uint8_t(255));  // opacity, as engines store it: not a glossy flag
      }
    };
    variants.push_back(v);
  }
  {
    Variant v{"hardware depth, reversed Z", {}, nullptr};
    v.desc.depthFormat = VK_FORMAT_D32_SFLOAT;
    v.desc.depthEncoding = gi::DepthEncoding::HardwareReversed;
    v.encode = [&](const CpuGBuffer&, const glm::mat4& proj, Encoded(&e)[6]) {
      ours(e);
      hardwareDepth(e[5], proj, true);
    };
    variants.push_back(v);
  }
  {
    Variant v{"hardware depth, forward Z, motion in UV", {}, nullptr};
    v.desc.depthFormat = VK_FORMAT_D32_SFLOAT;
    v.desc.depthEncoding = gi::DepthEncoding::Hardware;
    v.desc.motion = gi::MotionUnits::Uv;
    v.forwardZ = true;
    v.encode = [&](const CpuGBuffer& c, const glm::mat4& proj, Encoded(&e)[6]) {
      ours(e);
      hardwareDepth(e[5], proj, false);
      e[4].bytes.clear();
      for (size_t p = 0; p < n; ++p)
        for (int k = 0; k < 2; ++k) put(e[4].bytes, glm::packHalf1x16(c.motion[p][k] / float(kSize)));
    };
    variants.push_back(v);
  }

  {
    // A GPU rasterizer interpolates depth, it does not trace it: an NVIDIA H200's view depth differed
    // from lavapipe's by up to 2e-4 of the distance on walls at grazing angles (scripts/device/diag-depth), and points
    // reconstructed behind their surface had every ray blocked (the walls and floor rendered black).
    Variant v{"view depth 2e-4 too far (a GPU rasterizer's error)", {}, nullptr};
    v.encode = [&](const CpuGBuffer& c, const glm::mat4&, Encoded(&e)[6]) {
      ours(e);
      e[5].bytes.clear();
      for (size_t p = 0; p < n; ++p) put(e[5].bytes, c.viewZ[p] * (1.0f + 2e-4f));
    };
    variants.push_back(v);
  }
  {
    Variant v{"a y-up projection (negative-height viewport)", {}, nullptr};
    v.encode = [&](const CpuGBuffer&, const glm::mat4&, Encoded(&e)[6]) { ours(e); };
    v.yUp = true;
    variants.push_back(v);
  }

  // One frame of raw (direct light and one indirect path per pixel) per encoding.
  std::vector<engine::ReferenceImages> images;
  for (const Variant& v : variants) {
    const gpu::GpuCamera& cam = v.forwardZ ? forward : reversed;
    Encoded encoded[6];
    v.encode(g, clipFromView(cam), encoded);
    UploadedGBuffer uploaded = upload(ctx, encoded);
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
    desc.gbuffer = v.desc;
    desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    gi::Module* module = nullptr;
    gi::Error e = gi::create(desc, gi::Settings{}, module);
    ASSERT_FALSE(e) << v.what << ": " << e.message;
    gi::FrameInputs in;
    in.gbuffer = uploaded.views();
    in.camera = in.previousCamera = engine::moduleCamera(cam);
    if (v.yUp)
      for (int c = 0; c < 4; ++c)
        in.camera.clipFromView[c * 4 + 1] = in.previousCamera.clipFromView[c * 4 + 1] *= -1.0f;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { ASSERT_FALSE(gi::recordFrame(module, cmd, in)); });
    const gi::Outputs o = gi::outputs(module);
    engine::ReferenceImages out;
    out.final = readbackRgbOrFail(ctx, o.composite, o.compositeFormat, {kSize, kSize});
    out.direct = readbackRgbOrFail(ctx, o.direct, o.format, {kSize, kSize});
    images.push_back(out);
    gi::destroy(module);
    for (engine::Image& img : uploaded.images) engine::destroyImage(ctx, img);
  }
  // Our encoding through the adapter is the native path exactly; the others
  // differ by their quantisation (8-bit sRGB albedo, 10-bit normals, depth
  // through the projection), which moves shading points and normals a little:
  // a few pixels whose shadow ray grazes an edge flip between lit and shadowed.
  // The direct light's relative L1 and the final image's mean within 1%.
  const double finalMean = meanOf(images[0].final);
  ASSERT_GT(finalMean, 0.0);
  for (size_t i = 0; i < variants.size(); ++i) {
    double diff = 0.0, sum = 0.0;
    size_t worstAt = 0;
    double worst = 0.0;
    for (size_t k = 0; k < images[i].direct.pixels.size(); ++k) {
      const double a = images[i].direct.pixels[k], b = images[0].direct.pixels[k];
      diff += std::fabs(a - b);
      sum += std::fabs(b);
      if (std::fabs(a - b) > worst) {
        worst = std::fabs(a - b);
        worstAt = k;
      }
    }
    const double meanShift = std::fabs(meanOf(images[i].final) / finalMean - 1.0);
    const size_t p = worstAt / 3;
    std::printf(
        "%-45s direct: relative L1 %.2e (worst at %zu: %.4f vs %.4f, n %.4f %.4f %.4f z %.4f); final mean %+.2e\n",
        variants[i].what, diff / sum, p, images[i].direct.pixels[worstAt], images[0].direct.pixels[worstAt],
        g.normal[p].x, g.normal[p].y, g.normal[p].z, g.viewZ[p], meanShift);
    EXPECT_LT(diff / sum, 0.01) << variants[i].what;
    EXPECT_LT(meanShift, 0.01) << variants[i].what;
  }
}

// A camera that is not finite, not invertible or not a perspective
// projection is a named error, and records nothing.
TEST_F(GBufferEncodingsTest, BadCamerasAreNamedErrors) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-simple/cornell_simple.gltf"), s));
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, session));
  const gi::CameraDesc good = engine::moduleCamera(engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr));
  struct Case {
    const char* what;
    std::function<void(gi::CameraDesc&)> edit;
    const char* message;
  };
  const Case cases[] = {
      {"NaN in the view", [](gi::CameraDesc& c) { c.viewFromWorld[12] = std::nanf(""); }, "not finite"},
      {"a flattened view", [](gi::CameraDesc& c) { c.viewFromWorld[0] = c.viewFromWorld[5] = 0.0f; }, "not invertible"},
      {"an orthographic projection",
       [](gi::CameraDesc& c) {
         c.clipFromView[11] = 0.0f;
         c.clipFromView[15] = 1.0f;
       },
       "not a perspective projection"},
  };
  for (const Case& c : cases) {
    gi::FrameInputs in;
    in.gbuffer = tools::gbufferViews(session.gbuffer);
    in.camera = in.previousCamera = good;
    c.edit(in.camera);
    gi::Error e;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::recordFrame(session.module, cmd, in); });
    EXPECT_EQ(e.code, gi::ErrorCode::OutOfRange) << c.what;
    EXPECT_NE(e.message.find("inputs.camera"), std::string::npos) << e.message;
    EXPECT_NE(e.message.find(c.message), std::string::npos) << e.message;
  }
}

// Encodings that do not match their format, and formats the module does not
// read, are named errors at create.
TEST_F(GBufferEncodingsTest, MismatchedEncodingsAreNamedErrors) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-simple/cornell_simple.gltf"), s));
  struct Case {
    const char* what;
    std::function<void(gi::GBufferDesc&)> edit;
    std::vector<const char*> mentions;  // the field, and the names a person needs to fix it
  };
  const Case cases[] = {
      {"octahedral in rgba16f",
       [](gi::GBufferDesc& d) { d.normalEncoding = gi::NormalEncoding::Octahedral; },
       {"desc.gbuffer.normalFormat", "R16G16B16A16Sfloat (VkFormat 97)", "NormalEncoding::Octahedral", "R16G16Unorm",
        "R8G8Unorm"}},
      {"hardware depth in r32f",
       [](gi::GBufferDesc& d) { d.depthEncoding = gi::DepthEncoding::Hardware; },
       {"desc.gbuffer.depthFormat", "R32Sfloat", "DepthEncoding::Hardware", "D32Sfloat"}},
      {"linear depth in d32",
       [](gi::GBufferDesc& d) { d.depthFormat = VK_FORMAT_D32_SFLOAT; },
       {"desc.gbuffer.depthFormat", "D32Sfloat", "DepthEncoding::LinearViewZ", "R32Sfloat", "R16Sfloat"}},
      {"rgb565 albedo",
       [](gi::GBufferDesc& d) { d.albedoFormat = VK_FORMAT_R5G6B5_UNORM_PACK16; },
       {"desc.gbuffer.albedoFormat", "R5G6B5UnormPack16", "R8G8B8A8Srgb"}},
      {"unknown normal encoding",
       [](gi::GBufferDesc& d) { d.normalEncoding = gi::NormalEncoding(9); },
       {"desc.gbuffer.normalEncoding = 9"}},
      {"depth in an attachment layout",
       [](gi::GBufferDesc& d) { d.depthLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL; },
       {"desc.gbuffer.depthLayout", "DepthStencilAttachmentOptimal"}},
      {"colour views in an attachment layout",
       [](gi::GBufferDesc& d) { d.colorLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL; },
       {"desc.gbuffer.colorLayout", "ColorAttachmentOptimal"}},
      {"unknown motion units",
       [](gi::GBufferDesc& d) { d.motion = gi::MotionUnits(3); },
       {"desc.gbuffer.motion = 3", "Ndc"}},
      {"zero motion scale", [](gi::GBufferDesc& d) { d.motionScale[1] = 0.0f; }, {"desc.gbuffer.motionScale[1]"}},
      {"NaN motion scale",
       [](gi::GBufferDesc& d) { d.motionScale[0] = std::nanf(""); },
       {"desc.gbuffer.motionScale[0]"}},
  };
  for (const Case& c : cases) {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {16, 16});
    c.edit(desc.gbuffer);
    gi::Module* m = nullptr;
    gi::Error e = gi::create(desc, gi::Settings{}, m);
    EXPECT_TRUE(e) << c.what;
    for (const char* mention : c.mentions)
      EXPECT_NE(e.message.find(mention), std::string::npos) << c.what << ": \"" << mention << "\" not in " << e.message;
    EXPECT_EQ(m, nullptr);
  }
  // A frame without one of the six views names it.
  gi::Module* m = nullptr;
  ASSERT_FALSE(gi::create(tools::moduleDesc(ctx, s.gpu, {16, 16}), gi::Settings{}, m));
  ScopedSession native(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {16, 16}, gi::Settings{}, native));
  const char* names[] = {"normal", "albedo", "material", "emission", "motion", "depth"};
  for (int missing = 0; missing < 6; ++missing) {
    gi::FrameInputs in;
    in.gbuffer = tools::gbufferViews(native.gbuffer);
    VkImageView* views[] = {&in.gbuffer.normal,   &in.gbuffer.albedo, &in.gbuffer.material,
                            &in.gbuffer.emission, &in.gbuffer.motion, &in.gbuffer.depth};
    *views[missing] = VK_NULL_HANDLE;
    const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], 16, 16, nullptr);
    in.camera = in.previousCamera = engine::moduleCamera(cam);
    gi::Error e;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { e = gi::recordFrame(m, cmd, in); });
    EXPECT_EQ(e.code, gi::ErrorCode::MissingHandle) << names[missing];
    EXPECT_NE(e.message.find(std::string("inputs.gbuffer.") + names[missing] + " is VK_NULL_HANDLE"), std::string::npos)
        << e.message;
  }
  tools::destroyModuleSession(ctx, native);
  gi::destroy(m);
}

// Motion in every convention gi::GBufferDesc accepts reprojects exactly as ours (pixels, previous −
// current, the jitter in): temporal reprojection over a camera pan of about a pixel, both frames rendered
// with sub-pixel jitter, gives the same frame from our G-buffer's motion re-encoded in UV, in NDC, as
// current − previous, with y up, and without the jitter (the module adds the cameras' difference). The
// half floats round the motion a little. Declared as UV but handed pixels, or declared with the jitter
// but handed it without, the history lands elsewhere: the frame differs, so the test sees each convention.
TEST_F(GBufferEncodingsTest, MotionInEveryConventionReprojectsAsOurs) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-simple/cornell_simple.gltf"), s));
  engine::Camera moved = s.scene.cameras[0];
  moved.worldFromView[3] += moved.worldFromView[0] * 0.05f;
  // Jitter of (0.3, −0.2) and (−0.4, 0.35) pixels (TAA's); previous − current, in pixels.
  const glm::vec2 jitterA(0.3f, -0.2f), jitterB(-0.4f, 0.35f), jitterMotion = jitterA - jitterB;
  const float n = float(kSize);
  const gpu::GpuCamera a = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr, 2.0f * jitterA / n);
  const gpu::GpuCamera b = engine::makeGpuCamera(moved, kSize, kSize, &a, 2.0f * jitterB / n);
  ScopedSession native(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, native));
  CpuGBuffer frames[2];
  for (int f = 0; f < 2; ++f) {
    submitOrFail(ctx, [&](VkCommandBuffer cmd) {
      engine::recordGBuffer(ctx, cmd, native.gbufferPass, s.scene, s.gpu, native.gbuffer, f == 0 ? a : b, nullptr);
    });
    frames[f] = readGBuffer(ctx, native.gbuffer);
  }
  double largest = 0.0;
  for (const glm::vec2& m : frames[1].motion) largest = std::max(largest, double(glm::length(m)));
  ASSERT_GT(largest, 0.3) << "the pan should move the picture";

  struct Run {
    const char* what;
    gi::MotionUnits units;
    glm::vec2 declaredScale;  // GBufferDesc::motionScale
    bool declaredJitter;      // GBufferDesc::motionHasJitter
    glm::vec2 scale, offset;  // our pixel motion × scale + offset is what the module is handed
    bool same;                // the frame should be ours
  };
  const Run runs[] = {
      {"pixels (ours)", gi::MotionUnits::Pixels, {1, 1}, true, {1, 1}, {0, 0}, true},
      {"uv", gi::MotionUnits::Uv, {1, 1}, true, {1 / n, 1 / n}, {0, 0}, true},
      {"ndc", gi::MotionUnits::Ndc, {1, 1}, true, {2 / n, 2 / n}, {0, 0}, true},
      {"current - previous", gi::MotionUnits::Pixels, {-1, -1}, true, {-1, -1}, {0, 0}, true},
      {"uv, y up", gi::MotionUnits::Uv, {1, -1}, true, {1 / n, -1 / n}, {0, 0}, true},
      {"jitter left out", gi::MotionUnits::Pixels, {1, 1}, false, {1, 1}, -jitterMotion, true},
      {"uv declared, pixels given", gi::MotionUnits::Uv, {1, 1}, true, {1, 1}, {0, 0}, false},
      {"jitter declared in, left out", gi::MotionUnits::Pixels, {1, 1}, true, {1, 1}, -jitterMotion, false},
  };
  std::vector<engine::ReferenceImages> images;
  for (const Run& run : runs) {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
    desc.gbuffer.motion = run.units;
    desc.gbuffer.motionScale[0] = run.declaredScale.x;
    desc.gbuffer.motionScale[1] = run.declaredScale.y;
    desc.gbuffer.motionHasJitter = run.declaredJitter;
    desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    gi::Settings settings;
    settings.raw.temporalReprojection = true;
    gi::Module* module = nullptr;
    ASSERT_FALSE(gi::create(desc, settings, module));
    for (uint32_t f = 0; f < 2; ++f) {
      Encoded encoded[6];
      encodeOurs(frames[f], encoded, run.scale, f == 0 ? glm::vec2(0.0f) : run.scale * run.offset);
      UploadedGBuffer uploaded = upload(ctx, encoded);
      gi::FrameInputs in;
      in.gbuffer = uploaded.views();
      in.camera = engine::moduleCamera(f == 0 ? a : b);
      in.previousCamera = engine::moduleCamera(a);
      in.frameIndex = f;
      submitOrFail(ctx, [&](VkCommandBuffer cmd) { ASSERT_FALSE(gi::recordFrame(module, cmd, in)); });
      for (engine::Image& img : uploaded.images) engine::destroyImage(ctx, img);
    }
    const gi::Outputs o = gi::outputs(module);
    engine::ReferenceImages out;
    out.indirect = readbackRgbOrFail(ctx, o.indirect, o.format, {kSize, kSize});
    out.direct = readbackRgbOrFail(ctx, o.direct, o.format, {kSize, kSize});
    images.push_back(out);
    gi::destroy(module);
  }
  tools::destroyModuleSession(ctx, native);
  auto relativeL1 = [](const engine::FloatImage& x, const engine::FloatImage& y) {
    double diff = 0.0, sum = 0.0;
    for (size_t k = 0; k < x.pixels.size(); ++k) {
      diff += std::fabs(double(x.pixels[k]) - y.pixels[k]);
      sum += std::fabs(double(y.pixels[k]));
    }
    return diff / sum;
  };
  for (size_t r = 1; r < std::size(runs); ++r) {
    const double indirect = relativeL1(images[r].indirect, images[0].indirect);
    const double direct = relativeL1(images[r].direct, images[0].direct);
    std::printf("motion %s against ours: indirect relative L1 %.2e, direct %.2e\n", runs[r].what, indirect, direct);
    if (runs[r].same) {
      EXPECT_LT(indirect, 1e-3) << runs[r].what;
      EXPECT_LT(direct, 1e-3) << runs[r].what;
    } else {
      EXPECT_GT(indirect, 1e-2) << runs[r].what;
    }
  }
}

// The engine's layouts (issue 35 §5): a G-buffer read in SHADER_READ_ONLY_OPTIMAL (colour and depth) and
// outputs kept between frames in SHADER_READ_ONLY_OPTIMAL or TRANSFER_SRC_OPTIMAL give bit for bit the
// frames of GENERAL everywhere, 3 frames of svgf with 2 in flight, under synchronization validation.
TEST(GBufferLayouts, ReadOnlyGBufferAndOutputsInTheEnginesLayoutGiveTheSameFrames) {
  engine::Context ctx;
  std::string error;
  ASSERT_TRUE(createSyncValidatedContext(ctx, error)) << error;
  LoadedScene s;
  ASSERT_TRUE(engine::loadSceneForRendering(sharedScene("cornell-simple/cornell_simple.gltf"), s.scene, error))
      << error;
  s.upload(ctx);
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  ScopedSession native(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, native));
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    engine::recordGBuffer(ctx, cmd, native.gbufferPass, s.scene, s.gpu, native.gbuffer, cam, nullptr);
  });
  Encoded encoded[6];
  encodeOurs(readGBuffer(ctx, native.gbuffer), encoded);
  tools::destroyModuleSession(ctx, native);

  struct Layouts {
    const char* what;
    VkImageLayout gbuffer, outputs;
  };
  const Layouts runs[] = {{"GENERAL everywhere", VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL},
                          {"read-only G-buffer, sampled outputs", VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                           VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                          {"read-only G-buffer, copied outputs", VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                           VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL}};
  std::vector<engine::FloatImage> composites;
  for (const Layouts& run : runs) {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
    desc.gbuffer.glossy = gi::GlossyFlag::AlbedoAlpha;
    desc.gbuffer.colorLayout = desc.gbuffer.depthLayout = run.gbuffer;
    desc.outputLayout = run.outputs;
    desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    gi::Settings settings;
    settings.method = gi::Method::Svgf;
    gi::Module* module = nullptr;
    ASSERT_FALSE(gi::create(desc, settings, module)) << run.what;
    UploadedGBuffer uploaded = upload(ctx, encoded, run.gbuffer);
    engine::FrameSlots slots = engine::createFrameSlots(ctx, error, 2);
    for (uint32_t f = 0; f < 3; ++f) {
      engine::waitFrameSlot(ctx, slots, f, error);
      VkCommandBuffer cmd = engine::beginFrameSlot(ctx, slots, f, error);
      ASSERT_EQ(error, "") << run.what;
      gi::FrameInputs in;
      in.gbuffer = uploaded.views();
      in.camera = in.previousCamera = engine::moduleCamera(cam);
      in.frameIndex = f;
      ASSERT_FALSE(gi::recordFrame(module, cmd, in)) << run.what;
      ASSERT_TRUE(engine::submitFrameSlot(ctx, slots, f, error)) << error;
    }
    vkDeviceWaitIdle(ctx.device);
    const gi::Outputs o = gi::outputs(module);
    composites.push_back(readbackRgbOrFail(ctx, o.composite, o.compositeFormat, {kSize, kSize}, 1.0f, run.outputs));
    engine::destroyFrameSlots(ctx, slots);
    for (engine::Image& img : uploaded.images) engine::destroyImage(ctx, img);
    gi::destroy(module);
  }
  for (size_t r = 1; r < std::size(runs); ++r) EXPECT_TRUE(sameBits(composites[r], composites[0])) << runs[r].what;
  EXPECT_EQ(ctx.validationMessages(), 0u) << "validation (synchronization included) reported problems";
  s.release();
  engine::destroyContext(ctx);
}

// A G-buffer without an emission view (GBufferDesc::hasEmission = false, the view left null): the module
// leaves emission to the engine. On the Cornell box (its ceiling lamp in view), one raw frame: the
// indirect light is bit for bit the same, and the direct and composite outputs differ from the full
// G-buffer's by the emission image alone.
TEST_F(GBufferEncodingsTest, WithoutAnEmissionViewTheEngineAddsTheEmission) {
  LoadedScene s;
  ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), s));
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], kSize, kSize, nullptr);
  ScopedSession native(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {kSize, kSize}, gi::Settings{}, native));
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    engine::recordGBuffer(ctx, cmd, native.gbufferPass, s.scene, s.gpu, native.gbuffer, cam, nullptr);
  });
  const CpuGBuffer g = readGBuffer(ctx, native.gbuffer);
  tools::destroyModuleSession(ctx, native);
  Encoded encoded[6];
  encodeOurs(g, encoded);
  UploadedGBuffer uploaded = upload(ctx, encoded);
  engine::ReferenceImages out[2];
  for (int withEmission = 1; withEmission >= 0; --withEmission) {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {kSize, kSize});
    desc.gbuffer.hasEmission = withEmission != 0;
    desc.outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    gi::Module* module = nullptr;
    ASSERT_FALSE(gi::create(desc, gi::Settings{}, module));
    gi::FrameInputs in;
    in.gbuffer = uploaded.views();
    if (!withEmission) in.gbuffer.emission = VK_NULL_HANDLE;
    in.camera = in.previousCamera = engine::moduleCamera(cam);
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { ASSERT_FALSE(gi::recordFrame(module, cmd, in)); });
    const gi::Outputs o = gi::outputs(module);
    out[withEmission].direct = readbackRgbOrFail(ctx, o.direct, o.format, {kSize, kSize});
    out[withEmission].indirect = readbackRgbOrFail(ctx, o.indirect, o.format, {kSize, kSize});
    out[withEmission].final = readbackRgbOrFail(ctx, o.composite, o.compositeFormat, {kSize, kSize});
    gi::destroy(module);
  }
  for (engine::Image& img : uploaded.images) engine::destroyImage(ctx, img);
  double emitted = 0.0, worstDirect = 0.0, worstComposite = 0.0;
  for (size_t p = 0; p < g.emission.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const size_t k = 3 * p + size_t(c);
      const double e = g.emission[p][c];
      emitted += e;
      worstDirect = std::max(worstDirect, std::fabs(out[1].direct.pixels[k] - out[0].direct.pixels[k] - e) / (e + 1.0));
      worstComposite =
          std::max(worstComposite, std::fabs(out[1].final.pixels[k] - out[0].final.pixels[k] - e) / (e + 1.0));
    }
  std::printf("emission summed over the image %.1f; direct and composite differ from it by at most %.2e and %.2e\n",
              emitted, worstDirect, worstComposite);
  EXPECT_GT(emitted, 1.0) << "the lamp is in view";
  EXPECT_TRUE(sameBits(out[0].indirect, out[1].indirect));
  EXPECT_LT(worstDirect, 1e-5);
  EXPECT_LT(worstComposite, 1e-5);
}
