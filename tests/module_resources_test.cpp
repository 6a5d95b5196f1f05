// The module's resources as an engine sees them: out-of-memory is a returned
// error that leaves nothing behind, a failed setSettings keeps the module
// working, only the active method's memory is held, what a call replaces is
// released once the frames that used it are done, and a resize within the
// maximum size keeps the hash map.
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "gbuffer.h"
#include "gpu_test.h"
#include "module.h"
#include "module_test_helpers.h"

namespace {

// Host allocation callbacks that count live allocations and fail from the
// n-th call on (never, by default). Each block keeps its size and padding
// just below the pointer handed out, so reallocation copies what was there.
struct CountingAllocator {
  std::atomic<int64_t> live{0};
  std::atomic<uint64_t> calls{0};
  uint64_t failFrom = UINT64_MAX;

  static void* raw(size_t size, size_t alignment) {
    size_t pad = std::max<size_t>(alignment, 2 * sizeof(size_t));
    auto* base = static_cast<char*>(std::aligned_alloc(pad, (pad + size + pad - 1) / pad * pad));
    char* p = base + pad;
    reinterpret_cast<size_t*>(p)[-1] = size;
    reinterpret_cast<size_t*>(p)[-2] = pad;
    return p;
  }
  static void freeRaw(void* p) {
    size_t pad = static_cast<size_t*>(p)[-2];
    std::free(static_cast<char*>(p) - pad);
  }
  static void* allocate(void* user, size_t size, size_t alignment, VkSystemAllocationScope) {
    auto* a = static_cast<CountingAllocator*>(user);
    if (a->calls++ >= a->failFrom) return nullptr;
    a->live++;
    return raw(size, alignment);
  }
  static void* reallocate(void* user, void* old, size_t size, size_t alignment, VkSystemAllocationScope scope) {
    auto* a = static_cast<CountingAllocator*>(user);
    if (!old) return allocate(user, size, alignment, scope);
    if (size == 0) {
      release(user, old);
      return nullptr;
    }
    if (a->calls++ >= a->failFrom) return nullptr;
    void* fresh = raw(size, alignment);
    std::memcpy(fresh, old, std::min(size, static_cast<size_t*>(old)[-1]));
    freeRaw(old);
    return fresh;
  }
  static void release(void* user, void* memory) {
    if (!memory) return;
    static_cast<CountingAllocator*>(user)->live--;
    freeRaw(memory);
  }
  VkAllocationCallbacks callbacks() {
    VkAllocationCallbacks c{};
    c.pUserData = this;
    c.pfnAllocation = allocate;
    c.pfnReallocation = reallocate;
    c.pfnFree = release;
    return c;
  }
};

}  // namespace

class ModuleResourcesTest : public GpuTest {};

// A budget below what create needs: a VulkanCall error with
// VK_ERROR_OUT_OF_DEVICE_MEMORY, for every method, and no module.
TEST_F(ModuleResourcesTest, CreateBeyondTheMemoryBudgetIsAnError) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {64, 64});
  for (uint32_t i = 0; i < gi::kMethodCount; ++i) {
    gi::Settings settings;
    settings.method = gi::Method(i);
    desc.memoryBudgetBytes = 64 << 10;  // 64 KiB: the half-float outputs alone are 3 × 32 KiB
    gi::Module* m = nullptr;
    gi::Error e = gi::create(desc, settings, m);
    EXPECT_EQ(e.code, gi::ErrorCode::VulkanCall) << gi::methodName(settings.method) << ": " << e.message;
    EXPECT_EQ(e.result, VK_ERROR_OUT_OF_DEVICE_MEMORY) << e.message;
    EXPECT_NE(e.message.find("memoryBudgetBytes"), std::string::npos) << e.message;
    EXPECT_EQ(m, nullptr);
    // With room it works, and holds no more than the budget.
    desc.memoryBudgetBytes = 64 << 20;
    ASSERT_FALSE(gi::create(desc, settings, m)) << gi::methodName(settings.method);
    EXPECT_LE(m->gpu.memory.held, desc.memoryBudgetBytes);
    gi::destroy(m);
  }
}

// The engine's host allocator failing at every point of create in turn:
// each failure is a VulkanCall error, and every object made before it is
// destroyed again (the callbacks see as many frees as allocations).
TEST_F(ModuleResourcesTest, FailingHostAllocationsAreErrorsThatLeakNothing) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {32, 32});
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  CountingAllocator counting;
  VkAllocationCallbacks callbacks = counting.callbacks();
  desc.allocationCallbacks = &callbacks;
  gi::Module* m = nullptr;
  ASSERT_FALSE(gi::create(desc, settings, m));
  gi::destroy(m);
  EXPECT_EQ(counting.live, 0);
  const uint64_t calls = counting.calls;
  ASSERT_GT(calls, 10u) << "the driver does not use the engine's allocator; nothing to test";
  uint32_t failures = 0;
  const uint32_t messagesBefore = ctx.validationMessages();
  for (uint64_t n = 0; n < calls; n += std::max<uint64_t>(1, calls / 40)) {
    counting.calls = 0;
    counting.failFrom = n;
    m = nullptr;
    gi::Error e = gi::create(desc, settings, m);
    if (e) {
      failures++;
      EXPECT_EQ(e.code, gi::ErrorCode::VulkanCall) << "failing from allocation " << n << ": " << e.message;
      EXPECT_NE(e.result, VK_SUCCESS);
      EXPECT_EQ(m, nullptr);
    } else {
      gi::destroy(m);
    }
    EXPECT_EQ(counting.live, 0) << "failing from allocation " << n;
  }
  EXPECT_GT(failures, 0u);
  // The validation layer warns about most calls that returned
  // VK_ERROR_OUT_OF_HOST_MEMORY (measured: 41 warnings for 45 provoked
  // failures): at most one per failure, and those are taken off the count
  // the fixture checks.
  EXPECT_LE(ctx.validationMessages() - messagesBefore, failures);
  ctx.validation->warnings -= ctx.validationMessages() - messagesBefore;
}

// setSettings that runs out of memory returns the error and leaves the
// module as it was: the old method keeps rendering.
TEST_F(ModuleResourcesTest, SetSettingsOutOfMemoryKeepsThePreviousSettings) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{48, 32};
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
  gi::Settings settings;  // raw: a few small images
  ScopedSession session(ctx);
  desc.memoryBudgetBytes = 3 << 20;  // raw fits; gif's images do not double it
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  const uint64_t heldBefore = session.module->gpu.memory.held;
  gi::Settings gif = settings;
  gif.method = gi::Method::Gif;
  gif.gif.subsample = 1;  // its 8 statistics images at full size (8 × 24 KiB): more than the blocks have free
  session.module->gpu.memory.budget = heldBefore + (64 << 10);  // room for the programs' nothing, not for gif's images
  gi::Error e = gi::setSettings(session.module, gif);
  EXPECT_EQ(e.code, gi::ErrorCode::VulkanCall) << e.message;
  EXPECT_EQ(e.result, VK_ERROR_OUT_OF_DEVICE_MEMORY) << e.message;
  EXPECT_EQ(session.module->gpu.memory.held, heldBefore) << "the half-built gif resources were released";
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 1);
  gi::FrameStats st = gi::stats(session.module);
  ASSERT_FALSE(st.passes.empty());
  EXPECT_EQ(st.passes.front().name, "raw_trace") << "the module still runs raw";
  session.module->gpu.memory.budget = 0;
  ASSERT_FALSE(gi::setSettings(session.module, gif));
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 2);
  EXPECT_EQ(gi::stats(session.module).passes.front().name, "raw_trace");  // gif traces with raw_trace, then filters
  EXPECT_EQ(gi::stats(session.module).passes.back().name, "composite");
}

// Issue 17's budget: the demo's default method (hpsf) at 1080p, otherwise
// with the defaults, holds at most 150 MB of device memory (blocks, not only
// what is used).
TEST_F(ModuleResourcesTest, HpsfAt1080pHoldsAtMost150MB) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gi::Settings settings;
  settings.method = gi::Method::Hpsf;
  gi::Module* m = nullptr;
  ASSERT_FALSE(gi::create(tools::moduleDesc(ctx, s.gpu, {1920, 1080}), settings, m));
  EXPECT_TRUE(m->plan.packedHistory) << "the default hpsf reprojects its direct light: its history counts";
  EXPECT_LE(m->gpu.memory.held, VkDeviceSize(150'000'000)) << m->gpu.memory.held << " bytes";
  std::printf("hpsf at 1080p: %.1f MB held, %.1f MB used\n", m->gpu.memory.held * 1e-6, m->gpu.memory.used * 1e-6);
  // What it holds is what it needs: three half-float outputs, the map (2^19 cells: keys, sums, counts
  // and cells) and the packed direct history (8 bytes a pixel), with under 2 MB of anything else (lavapipe:
  // 0.04 MB) and under 1% of the blocks unused. The driver may pad each 1080p image (an NVIDIA H200 pads
  // an 8-byte one by 1.1 MB, its rows to a multiple of its tiles): that padding is the driver's, asked
  // for the four screen images here, not the module's.
  const VkDeviceSize pixels = 1920 * 1080, cells = VkDeviceSize(1) << 19;
  const VkDeviceSize needed =
      3 * 8 * pixels + cells * (2 * sizeof(uint32_t) + sizeof(gpu::HgAccum) + sizeof(gpu::HgCell)) + 8 * pixels;
  const VkDeviceSize padding = 4 * (driverImageBytes(ctx, {1920, 1080}, VK_FORMAT_R16G16B16A16_SFLOAT) - 8 * pixels);
  std::printf("the driver pads an 8-byte 1080p image by %.2f MB\n", (padding / 4) * 1e-6);
  EXPECT_GE(m->gpu.memory.used, needed);
  EXPECT_LE(m->gpu.memory.used, needed + padding + (VkDeviceSize(2) << 20));
  EXPECT_LE(m->gpu.memory.held - m->gpu.memory.used, m->gpu.memory.held / 100);
  gi::destroy(m);
}

// Memory follows the method: raw holds no filter images and no hash map;
// after switching from gif back to raw the gif images are released once the
// frames that used them are done.
TEST_F(ModuleResourcesTest, OnlyTheActiveMethodsMemoryIsHeld) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{64, 64};
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  ScopedSession session(ctx);
  gi::Settings raw;
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, raw, session));
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
  const uint64_t rawBytes = gi::stats(session.module).memoryUsedBytes;
  const uint64_t image = 64 * 64 * 16;
  // Outputs, noisy indirect and 1×1 placeholders, uniforms and counters: about 4 images.
  EXPECT_LT(rawBytes, 5 * image) << rawBytes << " bytes";
  gi::Settings gif = raw;
  gif.method = gi::Method::Gif;
  const gi::Outputs before = gi::outputs(session.module);
  ASSERT_FALSE(gi::setSettings(session.module, gif));
  const gi::Outputs after = gi::outputs(session.module);
  EXPECT_EQ(before.composite, after.composite) << "a new method keeps the output images (only resize replaces them)";
  EXPECT_EQ(before.indirectView, after.indirectView);
  tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 1);
  const uint64_t gifBytes = gi::stats(session.module).memoryUsedBytes;
  // gif's statistics images (1/s² of an image each), its guidance, its temporal reprojection's two sets of
  // direct and indirect history (half floats) and one guide (a word a pixel); raw's noisy indirect (half
  // floats) it does not hold: it traces into the indirect output and filters the history.
  const uint64_t perStatistic = uint64_t(gif.gif.subsample) * gif.gif.subsample;
  EXPECT_GE(gifBytes, rawBytes - image / 2 + FILTER_STACK * image / perStatistic + image / 2 + 2 * image + image / 4)
      << gifBytes;
  ASSERT_FALSE(gi::setSettings(session.module, raw));
  // The gif images stay until the frames that read them have completed
  // (framesInFlight = 2: frame 1 is done once frame 3 is recorded).
  EXPECT_GE(session.module->gpu.memory.used, gifBytes);
  for (uint32_t f = 2; f < 4; ++f) tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  EXPECT_EQ(session.module->retired.size(), 0u);
  EXPECT_EQ(gi::stats(session.module).memoryUsedBytes, rawBytes);
}

// Dynamic resolution: within the maximum size given at create, resize keeps
// the hash map (the same buffers, cells and all) and every image; beyond it they are new.
TEST_F(ModuleResourcesTest, ResizeWithinTheMaximumKeepsTheHashMapAndTheImages) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, {48, 32});
  desc.maxWidth = 64;
  desc.maxHeight = 48;
  gi::Settings settings;
  settings.method = gi::Method::Anhpsf;
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, {48, 32}, settings, session, &desc));
  auto frames = [&](uint32_t first, uint32_t count) {
    gpu::GpuCamera cam =
        engine::makeGpuCamera(s.scene.cameras[0], session.extent.width, session.extent.height, nullptr);
    for (uint32_t f = first; f < first + count; ++f)
      tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, f);
  };
  frames(0, 4);
  const VkBuffer cells = session.module->hash.cells.buffer;
  const uint32_t occupied = gi::stats(session.module).hash.occupied;
  ASSERT_GT(occupied, 0u);
  std::string error;
  const VkImage composite = gi::outputs(session.module).composite;
  const uint64_t held = session.module->gpu.memory.held;
  ASSERT_TRUE(tools::resizeModuleSession(ctx, session, {64, 48}, error)) << error;
  EXPECT_EQ(session.module->hash.cells.buffer, cells) << "a size within the maximum keeps the map";
  EXPECT_EQ(gi::outputs(session.module).composite, composite) << "and the images, made at the maximum";
  EXPECT_EQ(session.module->gpu.memory.held, held);
  frames(4, 1);
  EXPECT_GE(gi::stats(session.module).hash.occupied, occupied) << "the cells survived the resize";
  ASSERT_TRUE(tools::resizeModuleSession(ctx, session, {80, 48}, error)) << error;
  EXPECT_NE(session.module->hash.cells.buffer, cells) << "beyond the maximum the map is rebuilt";
  EXPECT_NE(gi::outputs(session.module).composite, composite) << "and the images, at the new maximum";
  frames(5, 2);
  EXPECT_GT(gi::stats(session.module).hash.occupied, 0u);
}

// Timestamps and labels are optional: without them the frame records no
// query (FrameStats still names every pass, with 0 ms) and renders the same.
TEST_F(ModuleResourcesTest, TimestampsOffRecordsNoQueriesAndTheSameImage) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{32, 24};
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  gi::Settings settings;
  settings.method = gi::Method::Gif;
  std::vector<float> images[2];
  std::vector<std::string> names[2];
  for (int timed = 0; timed < 2; ++timed) {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, s.gpu, size);
    desc.timestamps = timed == 1;
    desc.debugLabels = false;
    ScopedSession session(ctx);
    ASSERT_NO_FATAL_FAILURE(openSession(ctx, s, size, settings, session, &desc));
    EXPECT_EQ(session.module->timestamps != VK_NULL_HANDLE, timed == 1);
    tools::renderModuleFrame(ctx, session, s.scene, s.gpu, cam, cam, 0);
    gi::FrameStats st = gi::stats(session.module);
    for (const gi::PassTiming& p : st.passes) {
      names[timed].push_back(p.name);
      if (!timed) {
        EXPECT_EQ(p.ms, 0.0) << p.name;
      }
    }
    if (timed) {
      EXPECT_GT(st.totalMs, 0.0);
    }
    images[timed] = tools::readModuleImages(ctx, session).final.pixels;
  }
  EXPECT_EQ(names[0], names[1]);
  EXPECT_EQ(images[0], images[1]) << "the same seed and inputs give the same image with and without timing";
}

// gi.h's threading contract: modules are independent (each its own function
// table and memory), so two threads may create, record and destroy theirs at
// the same time. Each thread records into its own command pool; the queue is
// used from this thread only. Validation (with its thread-safety checks) stays silent.
TEST_F(ModuleResourcesTest, TwoModulesOnTwoThreadsAtOnce) {
  LoadedScene s;
  load(sharedScene("cornell-simple/cornell_simple.gltf"), s);
  const VkExtent2D size{32, 24};
  gpu::GpuCamera cam = engine::makeGpuCamera(s.scene.cameras[0], size.width, size.height, nullptr);
  std::string error;
  engine::GBuffer gbuffer = engine::createGBuffer(ctx, size, error);
  engine::GBufferPass pass = engine::createGBufferPass(ctx, s.gpu, error);
  ASSERT_EQ(error, "");
  submitOrFail(
      ctx, [&](VkCommandBuffer cmd) { engine::recordGBuffer(ctx, cmd, pass, s.scene, s.gpu, gbuffer, cam, nullptr); });
  const gi::GBufferViews views = tools::gbufferViews(gbuffer);
  struct Worker {
    gi::Method method;
    gi::Module* module = nullptr;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    gi::Error error;
  };
  Worker workers[2] = {{gi::Method::Hpsf}, {gi::Method::Gif}};
  auto run = [&](auto&& body) {
    std::thread a([&] { body(workers[0]); }), b([&] { body(workers[1]); });
    a.join();
    b.join();
  };
  // Create and record on two threads at once.
  run([&](Worker& w) {
    gi::Settings settings;
    settings.method = w.method;
    if ((w.error = gi::create(tools::moduleDesc(ctx, s.gpu, size), settings, w.module))) return;
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = ctx.queueFamily;
    EXPECT_EQ(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &w.pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = w.pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    EXPECT_EQ(vkAllocateCommandBuffers(ctx.device, &alloc, &w.cmd), VK_SUCCESS);
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    EXPECT_EQ(vkBeginCommandBuffer(w.cmd, &begin), VK_SUCCESS);
    w.error = gi::recordFrame(w.module, w.cmd, {views, engine::moduleCamera(cam), engine::moduleCamera(cam), 0});
    EXPECT_EQ(vkEndCommandBuffer(w.cmd), VK_SUCCESS);
  });
  for (Worker& w : workers) ASSERT_FALSE(w.error) << w.error.message;
  VkCommandBuffer cmds[] = {workers[0].cmd, workers[1].cmd};
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 2;
  submit.pCommandBuffers = cmds;
  EXPECT_EQ(vkQueueSubmit(ctx.queue, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
  EXPECT_EQ(vkQueueWaitIdle(ctx.queue), VK_SUCCESS);
  for (Worker& w : workers) {
    gi::FrameStats st;
    ASSERT_TRUE(gi::frameStats(w.module, 0, st));
    EXPECT_GT(st.raysTraced, 0u) << gi::methodName(w.method);
  }
  // Destroy on two threads at once.
  run([&](Worker& w) {
    gi::destroy(w.module);
    vkDestroyCommandPool(ctx.device, w.pool, nullptr);
  });
  engine::destroyGBufferPass(ctx, pass);
  engine::destroyGBuffer(ctx, gbuffer);
}
