// The foreign engine (examples/foreign_engine): a program that knows the
// module only by its public API, with its own device, glTF loading,
// reversed-Z octahedral G-buffer and jittered camera. Its mean indirect light
// on the Cornell box must match gi-render's for the same method and samples,
// with no validation message in either, whether its meshes are handed over
// as its own device buffers or as CPU arrays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "run_process.h"

namespace {

const std::string kCornell = std::string(GI_SHARED_SCENES) + "/cornell-box-mcguire/CornellBox-Original.gltf";

// "label: r g b" from the tool's output.
bool readTriple(const std::string& output, const std::string& label, double (&out)[3]) {
  size_t at = output.find(label + ":");
  if (at == std::string::npos) return false;
  std::istringstream in(output.substr(at + label.size() + 1));
  return bool(in >> out[0] >> out[1] >> out[2]);
}

// Mean rgb of a little-endian rgb .pfm.
bool pfmMean(const std::string& path, double (&out)[3]) {
  std::ifstream f(path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0;
  double scale = 0.0;
  if (!(f >> magic >> w >> h >> scale) || magic != "PF" || scale >= 0.0 || w <= 0 || h <= 0) return false;
  f.get();
  std::vector<float> rgb(size_t(w) * size_t(h) * 3);
  if (!f.read(reinterpret_cast<char*>(rgb.data()), std::streamsize(rgb.size() * sizeof(float)))) return false;
  for (int c = 0; c < 3; ++c) out[c] = 0.0;
  for (size_t p = 0; p < rgb.size() / 3; ++p)
    for (int c = 0; c < 3; ++c) out[c] += rgb[3 * p + size_t(c)] / double(w * h);
  return true;
}

}  // namespace

TEST(ForeignEngine, MeanIndirectMatchesGiRenderOnTheCornellBox) {
  const std::string dir = std::filesystem::temp_directory_path() / "foreign_engine_test";
  std::filesystem::create_directories(dir);
  const std::string common = " --size 64x64 --max-bounces 4 --validation --scene " + kCornell;
  std::string foreignOut, renderOut;
  ASSERT_EQ(runProcess(GI_FOREIGN_ENGINE_BINARY, "--method raw --frames 32" + common, foreignOut), 0) << foreignOut;
  EXPECT_NE(foreignOut.find("validation messages: 0"), std::string::npos) << foreignOut;
  ASSERT_EQ(
      runProcess(GI_RENDER_BINARY,
                 "--method raw --spp 1 --frames 32 --aov indirect --out " + dir + "/indirect.pfm" + common, renderOut),
      0)
      << renderOut;
  double foreign[3], error[3], render[3];
  ASSERT_TRUE(readTriple(foreignOut, "mean indirect", foreign)) << foreignOut;
  ASSERT_TRUE(readTriple(foreignOut, "standard error", error)) << foreignOut;
  ASSERT_TRUE(pfmMean(dir + "/indirect.pfm", render));
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(render[c], 0.0);
    // Both are means of 32 × 64² one-sample paths: the difference's standard
    // error is √2 times the foreign engine's. Four of those, and 1% for
    // what the jitter moves (the foreign engine samples across each pixel,
    // gi-render at its centre).
    const double tolerance = 4.0 * std::sqrt(2.0) * error[c] + 0.01 * render[c];
    std::printf("channel %d: foreign engine %.5f ± %.5f, gi-render %.5f (difference %+.2f%%, tolerance %.2f%%)\n", c,
                foreign[c], error[c], render[c], 100.0 * (foreign[c] / render[c] - 1.0), 100.0 * tolerance / render[c]);
    EXPECT_NEAR(foreign[c], render[c], tolerance) << "channel " << c;
  }
}

// The foreign engine hands the module its G-buffer's own vertex and index
// buffers (device addresses, interleaved stride 24) by default: the image
// must be the one the same meshes give as CPU arrays, bit for bit.
TEST(ForeignEngine, DeviceBufferMeshesRenderAsCpuArrays) {
  const std::string dir = std::filesystem::temp_directory_path() / "foreign_engine_test";
  std::filesystem::create_directories(dir);
  const std::string common = " --method raw --frames 4 --size 48x48 --validation --scene " + kCornell;
  std::string device, cpu;
  ASSERT_EQ(runProcess(GI_FOREIGN_ENGINE_BINARY, "--meshes device --out " + dir + "/device.pfm" + common, device), 0)
      << device;
  ASSERT_EQ(runProcess(GI_FOREIGN_ENGINE_BINARY, "--meshes cpu --out " + dir + "/cpu.pfm" + common, cpu), 0) << cpu;
  EXPECT_NE(device.find("from the G-buffer's device buffers"), std::string::npos) << device;
  EXPECT_NE(device.find("validation messages: 0"), std::string::npos) << device;
  EXPECT_NE(cpu.find("validation messages: 0"), std::string::npos) << cpu;
  std::ifstream a(dir + "/device.pfm", std::ios::binary), b(dir + "/cpu.pfm", std::ios::binary);
  const std::string bytesA((std::istreambuf_iterator<char>(a)), {}), bytesB((std::istreambuf_iterator<char>(b)), {});
  ASSERT_GT(bytesA.size(), 48u * 48u * 12u);
  EXPECT_TRUE(bytesA == bytesB) << "device-buffer meshes rendered another image";
}

TEST(ForeignEngine, BadInputIsANamedError) {
  std::string out;
  EXPECT_EQ(runProcess(GI_FOREIGN_ENGINE_BINARY, "--scene /no/such.gltf", out), 1) << out;
  EXPECT_NE(out.find("/no/such.gltf"), std::string::npos) << out;
  EXPECT_EQ(runProcess(GI_FOREIGN_ENGINE_BINARY, "--scene x.gltf --method magic", out), 1) << out;
  EXPECT_NE(out.find("unknown method magic"), std::string::npos) << out;
}

// Issue 35 §5: the engine reads everything in SHADER_READ_ONLY_OPTIMAL (its G-buffer, depth included)
// and keeps the outputs in the layout it samples them in, reading them in a fragment shader
// (examples/foreign_engine/present_pass.h) with 3 frames in flight for 100 frames: no validation
// message with synchronization validation on, for a method with history (svgf) and a hash method, and
// for svgf with the outputs in the engine's HDR format (B10G11R11, ModuleDesc::outputFormat), whose mean
// is the half-float run's to the packed format's steps.
TEST(ForeignEngine, OutputsSampledInAFragmentShaderForAHundredFramesThreeInFlight) {
  double means[2][3] = {};
  for (const char* run : {"svgf", "hpsf", "svgf --outputs packed"}) {
    std::string out;
    ASSERT_EQ(
        runProcess(GI_FOREIGN_ENGINE_BINARY,
                   std::string("--method ") + run + " --frames 100 --size 32x32 --validation --scene " + kCornell, out),
        0)
        << out;
    EXPECT_NE(out.find("100 frames (jittered, 3 in flight)"), std::string::npos) << out;
    EXPECT_NE(out.find("validation messages: 0"), std::string::npos) << out;
    const bool packed = std::string(run).find("packed") != std::string::npos;
    EXPECT_NE(out.find(packed ? "outputs: B10G11R11" : "outputs: RGBA16F"), std::string::npos) << out;
    if (std::string(run).rfind("svgf", 0) == 0) {
      ASSERT_TRUE(readTriple(out, "mean indirect", means[packed])) << out;
    }
  }
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(means[0][c], 0.0);
    EXPECT_NEAR(means[1][c], means[0][c], means[0][c] / 32.0) << "channel " << c;
  }
}
