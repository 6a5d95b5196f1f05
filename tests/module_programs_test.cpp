// The module's programs: listed per settings, readied on an engine's thread
// ahead of a method switch (gi::preparePrograms, and a warm-up of empty
// dispatches for drivers that compile at first dispatch) while frames go on,
// and created through the engine's pipeline cache.
#include <atomic>
#include <cstring>
#include <thread>

#include "module_test_helpers.h"
#include "readback.h"

namespace {

// Counts the module's vkCreateComputePipelines calls and the caches they
// name, through the loader entry point the test hands to gi::create.
struct PipelineCounter {
  std::atomic<uint32_t> pipelines{0};
  std::atomic<uint32_t> throughCache{0};  // of those, created through `cache`
  VkPipelineCache cache = VK_NULL_HANDLE;
  PFN_vkCreateComputePipelines create = nullptr;
  PFN_vkGetDeviceProcAddr getDeviceProcAddr = nullptr;
};
PipelineCounter counter;

VKAPI_ATTR VkResult VKAPI_CALL countedCreateComputePipelines(VkDevice device, VkPipelineCache cache, uint32_t count,
                                                             const VkComputePipelineCreateInfo* infos,
                                                             const VkAllocationCallbacks* allocator, VkPipeline* out) {
  counter.pipelines += count;
  if (cache != VK_NULL_HANDLE && cache == counter.cache) counter.throughCache += count;
  return counter.create(device, cache, count, infos, allocator, out);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countedGetDeviceProcAddr(VkDevice device, const char* name) {
  if (std::strcmp(name, "vkCreateComputePipelines") == 0) {
    counter.create = reinterpret_cast<PFN_vkCreateComputePipelines>(counter.getDeviceProcAddr(device, name));
    return reinterpret_cast<PFN_vkVoidFunction>(countedCreateComputePipelines);
  }
  return counter.getDeviceProcAddr(device, name);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL countedGetInstanceProcAddr(VkInstance instance, const char* name) {
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0) {
    counter.getDeviceProcAddr = reinterpret_cast<PFN_vkGetDeviceProcAddr>(vkGetInstanceProcAddr(instance, name));
    return reinterpret_cast<PFN_vkVoidFunction>(countedGetDeviceProcAddr);
  }
  return vkGetInstanceProcAddr(instance, name);
}

// Submits a recorded command buffer and waits for it.
void submitRecorded(const engine::Context& ctx, VkCommandBuffer cmd) {
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  vkCreateFence(ctx.device, &fenceInfo, nullptr, &fence);
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  EXPECT_EQ(vkQueueSubmit(ctx.queue, 1, &submit, fence), VK_SUCCESS);
  vkWaitForFences(ctx.device, 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(ctx.device, fence, nullptr);
}

gi::Settings hpsfSettings() {
  gi::Settings s;
  s.method = gi::Method::Hpsf;
  return s;
}

}  // namespace

class ModuleProgramsTest : public GpuTest {
 protected:
  static constexpr VkExtent2D kSize{32, 24};
  LoadedScene scene;
  VkPipelineCache cache = VK_NULL_HANDLE;

  void SetUp() override {
    ASSERT_NO_FATAL_FAILURE(load(sharedScene("cornell-box-mcguire/CornellBox-Original.gltf"), scene));
    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    ASSERT_EQ(vkCreatePipelineCache(ctx.device, &info, nullptr, &cache), VK_SUCCESS);
    counter.pipelines = 0;
    counter.throughCache = 0;
    counter.cache = cache;
  }
  void TearDown() override {
    vkDestroyPipelineCache(ctx.device, cache, nullptr);
    scene.release();
    GpuTest::TearDown();
  }
  // A module desc that creates its pipelines through the test's cache and counter.
  gi::ModuleDesc countedDesc() const {
    gi::ModuleDesc desc = tools::moduleDesc(ctx, scene.gpu, kSize);
    desc.getInstanceProcAddr = countedGetInstanceProcAddr;
    desc.pipelineCache = cache;
    return desc;
  }
  void renderFrames(tools::ModuleSession& session, uint32_t first, uint32_t count) {
    const gpu::GpuCamera cam = engine::makeGpuCamera(scene.scene.cameras[0], kSize.width, kSize.height, nullptr);
    for (uint32_t i = first; i < first + count; ++i)
      tools::renderModuleFrame(ctx, session, scene.scene, scene.gpu, cam, cam, i);
  }
};

TEST_F(ModuleProgramsTest, EveryPipelineGoesThroughTheEnginesCache) {
  const gi::ModuleDesc desc = countedDesc();
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, scene, kSize, gi::Settings{}, session, &desc));
  for (gi::Method method : {gi::Method::Gif, gi::Method::Aaf, gi::Method::Hpsf, gi::Method::Anhpsf, gi::Method::Svgf}) {
    gi::Settings s;
    s.method = method;
    ASSERT_FALSE(gi::setSettings(session.module, s));
    renderFrames(session, 0, 1);
  }
  tools::destroyModuleSession(ctx, session);
  EXPECT_GE(counter.pipelines.load(), 15u);  // raw's, then what each new method adds
  EXPECT_EQ(counter.throughCache.load(), counter.pipelines.load()) << "every pipeline names the engine's cache";
}

TEST_F(ModuleProgramsTest, ProgramsReadiedOnAnotherThreadLeaveTheSwitchNothingToCreate) {
  const gi::ModuleDesc desc = countedDesc();
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, scene, kSize, gi::Settings{}, session, &desc));
  const gi::Settings hpsf = hpsfSettings();
  const std::vector<std::string> names = gi::programNames(session.module, hpsf);
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "hpsf_insert");
  EXPECT_EQ(names.back(), "gi_composite");
  EXPECT_FALSE(gi::programsPrepared(session.module, hpsf));
  const uint32_t before = counter.pipelines;

  // The engine's thread readies hpsf and records its warm-up while this one renders raw.
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.queueFamilyIndex = ctx.queueFamily;
  ASSERT_EQ(vkCreateCommandPool(ctx.device, &poolInfo, nullptr, &pool), VK_SUCCESS);
  VkCommandBuffer warmup = VK_NULL_HANDLE;
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.commandBufferCount = 1;
  ASSERT_EQ(vkAllocateCommandBuffers(ctx.device, &alloc, &warmup), VK_SUCCESS);
  std::atomic<bool> ready{false};
  std::string workerError;
  std::thread worker([&] {
    if (gi::Error e = gi::preparePrograms(session.module, hpsf)) workerError = e.message;
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(warmup, &begin);
    if (gi::Error e = gi::recordProgramWarmup(session.module, hpsf, warmup)) workerError = e.message;
    vkEndCommandBuffer(warmup);
    ready = true;
  });
  uint32_t framesMeanwhile = 0;
  while (!ready || framesMeanwhile < 2) renderFrames(session, framesMeanwhile++, 1);
  worker.join();
  ASSERT_EQ(workerError, "");
  EXPECT_GE(framesMeanwhile, 2u);
  submitRecorded(ctx, warmup);
  gi::finishProgramWarmup(session.module);
  EXPECT_TRUE(gi::programsPrepared(session.module, hpsf));
  // One pipeline per program but the composite, which raw made already: all made on the engine's thread.
  EXPECT_EQ(counter.pipelines - before, names.size() - 1);

  const uint32_t prepared = counter.pipelines;
  ASSERT_FALSE(gi::setSettings(session.module, hpsf));
  EXPECT_EQ(counter.pipelines.load(), prepared) << "the switch created no pipeline";
  renderFrames(session, 0, 4);
  const engine::FloatImage warmed = tools::readModuleImages(ctx, session).final;
  tools::destroyModuleSession(ctx, session);
  vkDestroyCommandPool(ctx.device, pool, nullptr);

  // The warm-up ran nothing: the same frames as a module that never warmed.
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, scene, kSize, hpsf, session));
  renderFrames(session, 0, 4);
  const engine::FloatImage direct = tools::readModuleImages(ctx, session).final;
  tools::destroyModuleSession(ctx, session);
  ASSERT_EQ(warmed.pixels.size(), direct.pixels.size());
  EXPECT_EQ(std::memcmp(warmed.pixels.data(), direct.pixels.data(), direct.pixels.size() * sizeof(float)), 0);
}

TEST_F(ModuleProgramsTest, AWarmUpNamesItsProgramAndIsFinishedBeforeTheNext) {
  ScopedSession session(ctx);
  ASSERT_NO_FATAL_FAILURE(openSession(ctx, scene, kSize, gi::Settings{}, session));
  const gi::Settings hpsf = hpsfSettings();
  submitOrFail(ctx, [&](VkCommandBuffer cmd) {
    gi::Error unknown = gi::recordProgramWarmup(session.module, hpsf, cmd, "gi_raw_trace");
    EXPECT_EQ(unknown.code, gi::ErrorCode::OutOfRange);
    EXPECT_NE(unknown.message.find("\"gi_raw_trace\" is not one these settings run"), std::string::npos)
        << unknown.message;
    EXPECT_FALSE(gi::recordProgramWarmup(session.module, hpsf, cmd, "hpsf_resolve"));
    gi::Error twice = gi::recordProgramWarmup(session.module, hpsf, cmd);
    EXPECT_NE(twice.message.find("gi::finishProgramWarmup"), std::string::npos) << twice.message;
  });
  gi::finishProgramWarmup(session.module);
  // Every method's warm-up, one after another, records cleanly (validation on).
  for (gi::Method method : {gi::Method::Gif, gi::Method::Bilateral, gi::Method::Atrous, gi::Method::Aaf,
                            gi::Method::Sspsf, gi::Method::Nhpsf, gi::Method::Anhpsf, gi::Method::Svgf}) {
    gi::Settings s;
    s.method = method;
    submitOrFail(ctx, [&](VkCommandBuffer cmd) { EXPECT_FALSE(gi::recordProgramWarmup(session.module, s, cmd)); });
    gi::finishProgramWarmup(session.module);
  }
}
