// gi::predictMemory tells, without creating anything, exactly what a module will hold; and an
// engine's own device-memory allocator (ModuleDesc::deviceMemory) serves every byte a module holds,
// with the same frames as the module's own blocks.
//
// Every method at 1920×1080 holds what docs/RESULTS.md's memory table says
// (docs/results/memory/memory.csv, written by `scripts/bench memory` after one
// frame): held, used and transient bytes as the module is created, to within
// a block's rounding. A change that moves any method's memory fails here
// until the table is measured again; the goals the table compares against are
// issue 30's (200 MB, 150 for hpsf and svgf).
#include <fstream>
#include <map>
#include <sstream>

#include "engine_device_memory.h"
#include "gi/catalogue.h"
#include "module.h"
#include "module_test_helpers.h"

namespace {

struct MemoryRow {
  uint64_t held = 0, used = 0, transient = 0;
};

// The 1920×1080 rows of memory.csv by method (header: method,width,height,held_bytes,used_bytes,transient_bytes,blocks,
// predicted_bytes).
std::map<std::string, MemoryRow> fullHdRows(const std::string& path) {
  std::map<std::string, MemoryRow> out;
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  EXPECT_EQ(line, "method,width,height,held_bytes,used_bytes,transient_bytes,blocks,predicted_bytes") << path;
  while (std::getline(file, line)) {
    std::stringstream fields(line);
    std::string method, width, height, held, used, transient;
    std::getline(fields, method, ',');
    std::getline(fields, width, ',');
    std::getline(fields, height, ',');
    std::getline(fields, held, ',');
    std::getline(fields, used, ',');
    std::getline(fields, transient, ',');
    if (width == "1920" && height == "1080")
      out[method] = {std::stoull(held), std::stoull(used), std::stoull(transient)};
  }
  return out;
}

}  // namespace

class ModuleMemoryTest : public GpuTest {};

TEST_F(ModuleMemoryTest, EveryMethodAt1080pHoldsWhatTheMemoryTableSays) {
  // The table was measured on lavapipe, which pads no image. A driver that pads 1080p images holds more
  // for every method (an NVIDIA H200: 4.4 MB for anhpsf, 10 MB for svgf, and its transient buffer's
  // alignment); there what a module holds is checked against its prediction (the next test), not the table.
  const VkDeviceSize padding = driverImageBytes(ctx, {1920, 1080}, VK_FORMAT_R16G16B16A16_SFLOAT) - 8 * 1920 * 1080;
  if (padding != 0)
    GTEST_SKIP() << "this driver pads a 1080p image by " << padding << " bytes; the table is lavapipe's";
  const std::map<std::string, MemoryRow> table = fullHdRows(std::string(GI_RESULTS) + "/memory/memory.csv");
  LoadedScene s;
  load(std::string(GI_ASSETS) + "/cornell_box/cornell_box.gltf", s);
  constexpr uint64_t kSlack = 1u << 20;  // the block a placeholder or a small buffer lands in
  for (const gi::MethodInfo& info : gi::methodCatalogue()) {
    SCOPED_TRACE(info.name);
    ASSERT_EQ(table.count(info.name), 1u) << "memory.csv has no 1920x1080 row";
    const MemoryRow& row = table.at(info.name);
    gi::Settings settings;
    settings.method = info.method;
    gi::Module* m = nullptr;
    ASSERT_FALSE(gi::create(tools::moduleDesc(ctx, s.gpu, {1920, 1080}), settings, m));
    const uint64_t held = m->gpu.memory.held, used = m->gpu.memory.used, transient = m->sized.frameBytes;
    std::printf("%-9s held %.1f MB (table %.1f), used %.1f (%.1f), transient %.1f (%.1f)\n", info.name, held * 1e-6,
                row.held * 1e-6, used * 1e-6, row.used * 1e-6, transient * 1e-6, row.transient * 1e-6);
    EXPECT_NEAR(double(held), double(row.held), double(kSlack));
    // Issue 30's goal (the table's goal column, tools/results_tables.py's MEMORY_GOAL_MB): NRD's class.
    const bool tighter = info.method == gi::Method::Hpsf || info.method == gi::Method::Svgf;
    EXPECT_LE(held, tighter ? 150'000'000u : 200'000'000u) << "over issue 30's goal at 1080p";
    EXPECT_NEAR(double(used), double(row.used), double(kSlack));
    EXPECT_EQ(transient, row.transient);
    gi::destroy(m);
  }
}

// The prediction equals what create holds, field by field, for every method: at 1920×1080 and at an
// odd small size whose hash map is sized for a larger maximum, with two and three frames in flight,
// with the module's own blocks and with the engine's allocator. A budget the module would exceed is
// the error create would give.
TEST_F(ModuleMemoryTest, ThePredictionIsWhatTheModuleHolds) {
  LoadedScene s;
  load(std::string(GI_ASSETS) + "/cornell_box/cornell_box.gltf", s);
  EngineDeviceMemory engineMemory(ctx);
  struct Case {
    VkExtent2D size, maximum;
    uint32_t framesInFlight;
    bool engineAllocator;
    VkFormat outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // packed: the module's working pair, transient
  };
  const Case cases[] = {{{1920, 1080}, {0, 0}, 2, false},
                        {{97, 61}, {300, 200}, 3, false},
                        {{97, 61}, {0, 0}, 2, true},
                        {{97, 61}, {0, 0}, 2, true, VK_FORMAT_B10G11R11_UFLOAT_PACK32}};
  for (const Case& c : cases)
    for (const gi::MethodInfo& info : gi::methodCatalogue()) {
      SCOPED_TRACE(std::string(info.name) + " at " + std::to_string(c.size.width) + "x" +
                   std::to_string(c.size.height) + (c.engineAllocator ? " from the engine's allocator" : "") +
                   (c.outputFormat == VK_FORMAT_B10G11R11_UFLOAT_PACK32 ? ", packed outputs" : ""));
      gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, c.size);
      desc.outputFormat = c.outputFormat;
      desc.maxWidth = c.maximum.width;
      desc.maxHeight = c.maximum.height;
      desc.framesInFlight = c.framesInFlight;
      if (c.engineAllocator) desc.deviceMemory = engineMemory.callbacks();
      gi::Settings settings;
      settings.method = info.method;
      gi::MemoryPrediction predicted;
      ASSERT_FALSE(gi::predictMemory(desc, settings, predicted));
      EXPECT_EQ(engineMemory.requests, 0u) << "a prediction asks the engine for nothing";
      gi::Module* m = nullptr;
      ASSERT_FALSE(gi::create(desc, settings, m));
      EXPECT_EQ(predicted.heldBytes, m->gpu.memory.held);
      EXPECT_EQ(predicted.usedBytes, m->gpu.memory.used);
      EXPECT_EQ(predicted.transientBytes, m->sized.frameBytes);
      EXPECT_EQ(predicted.permanentBytes, m->gpu.memory.used - m->sized.frameBytes);
      EXPECT_EQ(predicted.deviceAllocations, m->gpu.memory.allocations);
      if (c.engineAllocator) {
        EXPECT_EQ(predicted.heldBytes, engineMemory.liveBytes);
        EXPECT_EQ(predicted.transientBytes, engineMemory.transientBytes)
            << "the requests say which images are transient";
        EXPECT_EQ(predicted.deviceAllocations, 0u);
      }
      gi::destroy(m);
      engineMemory.requests = 0;
    }
  EXPECT_EQ(engineMemory.liveBytes, 0u);
  EXPECT_TRUE(engineMemory.error.empty()) << engineMemory.error;
  // Beyond a budget: the error create gives, and nothing predicted.
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {1920, 1080});
  gi::Settings settings;
  gi::MemoryPrediction full;
  ASSERT_FALSE(gi::predictMemory(desc, settings, full));
  desc.memoryBudgetBytes = full.heldBytes - 1;
  gi::MemoryPrediction over;
  const gi::Error e = gi::predictMemory(desc, settings, over);
  EXPECT_EQ(e.code, gi::ErrorCode::VulkanCall) << e.message;
  EXPECT_EQ(e.result, VK_ERROR_OUT_OF_DEVICE_MEMORY);
  EXPECT_NE(e.message.find("memoryBudgetBytes"), std::string::npos) << e.message;
  EXPECT_EQ(over.heldBytes, 0u);
  gi::Module* m = nullptr;
  EXPECT_EQ(gi::create(desc, settings, m).result, VK_ERROR_OUT_OF_DEVICE_MEMORY);
  desc.memoryBudgetBytes = full.heldBytes;
  ASSERT_FALSE(gi::create(desc, settings, m)) << "the predicted bytes are enough";
  gi::destroy(m);
}

// With ModuleDesc::deviceMemory set the engine's allocator holds every byte the module holds, the
// module calls vkAllocateMemory not once (counted through the loader entry point it is given), its
// frames are bit for bit those it renders from its own blocks, a method switch frees the old method's
// slices once its frames are done, and destroy frees the rest. Half-baked callbacks are a named error.
TEST_F(ModuleMemoryTest, AnEnginesAllocatorHoldsEveryByteAndTheModuleAllocatesNone) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{48, 32};
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  EngineDeviceMemory engineMemory(ctx);
  const gi::Method methods[] = {gi::Method::Raw,  gi::Method::Gif,    gi::Method::Aaf, gi::Method::Sspsf,
                                gi::Method::Hpsf, gi::Method::Anhpsf, gi::Method::Svgf};
  for (gi::Method method : methods) {
    SCOPED_TRACE(gi::methodName(method));
    gi::Settings settings;
    settings.method = method;
    engine::ReferenceImages images[2];
    for (int engineOwned = 0; engineOwned < 2; ++engineOwned) {
      gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
      desc.getInstanceProcAddr = countingGetInstanceProcAddr;
      if (engineOwned) desc.deviceMemory = engineMemory.callbacks();
      moduleAllocateMemoryCalls = 0;
      ScopedSession session(ctx);
      ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
      for (uint32_t f = 0; f < 3; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
      const gi::FrameStats stats = gi::stats(session.module);
      if (engineOwned) {
        EXPECT_EQ(moduleAllocateMemoryCalls, 0u);
        EXPECT_EQ(stats.deviceAllocations, 0u);
        EXPECT_EQ(stats.memoryBytes, engineMemory.liveBytes);
        EXPECT_EQ(stats.memoryUsedBytes, engineMemory.liveBytes);
        EXPECT_EQ(stats.memoryTransientBytes, engineMemory.transientBytes);
      } else {
        EXPECT_GT(moduleAllocateMemoryCalls, 0u) << "the counter sees the module's own blocks";
      }
      images[engineOwned] = tools::readModuleImages(ctx, session);
    }
    EXPECT_EQ(engineMemory.liveBytes, 0u) << "destroy frees every slice";
    EXPECT_TRUE(sameBits(images[0].final, images[1].final));
    EXPECT_TRUE(sameBits(images[0].indirect, images[1].indirect));
  }
  // A switch: hpsf's slices (its hash map) go back once the frames that read them are done.
  {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
    desc.deviceMemory = engineMemory.callbacks();
    gi::Settings hpsf, svgf;
    hpsf.method = gi::Method::Hpsf;
    svgf.method = gi::Method::Svgf;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, hpsf, session, &desc));
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    ASSERT_FALSE(gi::setSettings(session.module, svgf));
    for (uint32_t f = 1; f < 4; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
    gi::MemoryPrediction predicted;
    ASSERT_FALSE(gi::predictMemory(desc, svgf, predicted));
    EXPECT_EQ(engineMemory.liveBytes, predicted.heldBytes) << "what svgf needs, nothing of hpsf's";
    EXPECT_EQ(gi::stats(session.module).memoryBytes, predicted.heldBytes);
    tools::destroyModuleSession(ctx, session);
    EXPECT_EQ(engineMemory.liveBytes, 0u);
  }
  EXPECT_EQ(engineMemory.requests, engineMemory.frees);
  EXPECT_TRUE(engineMemory.error.empty()) << engineMemory.error;
  gi::ModuleDesc half = tools::moduleDesc(ctx, s.gpu, size);
  half.deviceMemory.allocate = engineMemory.callbacks().allocate;
  gi::Module* m = nullptr;
  const gi::Error e = gi::create(half, gi::Settings{}, m);
  EXPECT_EQ(e.code, gi::ErrorCode::MissingHandle);
  EXPECT_NE(e.message.find("desc.deviceMemory.free must be set with desc.deviceMemory.allocate"), std::string::npos)
      << e.message;
  EXPECT_EQ(m, nullptr);
}

// Issue 30's host-aliased transient pool: the transient requests of ModuleDesc::deviceMemory carved from
// one block (sized by gi::predictMemory) that a buffer of the engine's aliases whole. Between the
// module's frames the engine uses that memory (fills the buffer with NaN): the frames are bit for bit
// those of a module whose transient images own their memory, with no validation message
// (synchronization validation included). (Every frame also starts the transient images from UNDEFINED,
// as aliased images need; lavapipe keeps no layout-dependent state, so this test would pass without
// that barrier: it shows that no contents carry over between frames and that the barriers order the
// engine's writes, not the layouts.)
TEST_F(ModuleMemoryTest, TransientImagesShareTheEnginesMemoryBetweenFrames) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{48, 32};
  const gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  for (gi::Method method : {gi::Method::Gif, gi::Method::Aaf, gi::Method::Atrous}) {
    SCOPED_TRACE(gi::methodName(method));
    gi::Settings settings;
    settings.method = method;
    engine::ReferenceImages images[2];
    for (int aliased = 0; aliased < 2; ++aliased) {
      gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
      EngineDeviceMemory engineMemory(ctx);
      desc.deviceMemory = engineMemory.callbacks();
      gi::MemoryPrediction predicted;
      ASSERT_FALSE(gi::predictMemory(desc, settings, predicted));
      ASSERT_GT(predicted.transientBytes, 0u);
      AliasedTransientPool pool(ctx, engineMemory, predicted.transientBytes + (VkDeviceSize(1) << 20));
      if (aliased) desc.deviceMemory = pool.callbacks();
      ScopedSession session(ctx);
      ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
      for (uint32_t f = 0; f < 4; ++f) {
        tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
        submitOrFail(ctx, [&](VkCommandBuffer cmd) {  // the engine's own use of the pool's bytes
          engine::memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
          vkCmdFillBuffer(cmd, pool.alias, 0, VK_WHOLE_SIZE, 0x7fc00000u);  // quiet NaN in every float
        });
      }
      if (aliased) {
        EXPECT_GT(pool.slices, 0u);
        EXPECT_EQ(engineMemory.transientBytes, 0u) << "every transient request came from the pool";
      }
      images[aliased] = tools::readModuleImages(ctx, session);
    }
    EXPECT_TRUE(sameBits(images[0].final, images[1].final));
    EXPECT_TRUE(sameBits(images[0].indirect, images[1].indirect));
  }
}
