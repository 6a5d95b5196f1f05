// Issue 30's heap corruption, isolated (stop 65): one-shot submissions of debug labels alone under the
// validation layer, as many a second as the machine takes. Each submission records `labels` begin/end label
// pairs and is submitted and waited for; --pattern free allocates and frees a command buffer and a fence
// per submission (what engine::submitAndWait did up to stop 64), --pattern reuse resets one of each, and
// --pattern engine submits through engine::submitAndWait as it is now. Not a ctest test: a reproducer whose
// outcome is a crash or none (docs/RESULTS.md, "Extremes": the heap corruption), run for minutes.
//   label_stress [--pattern free|reuse|engine] [--submissions N] [--labels L] [--sync 0|1]
#include "context.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

enum class Pattern { Free, Reuse, Engine };

struct Options {
  Pattern pattern = Pattern::Free;
  bool sync = true;  // the validation layer's synchronization checks too
  uint64_t submissions = 1000000;
  uint32_t labels = 16;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--pattern" && value == "free")
      o.pattern = Pattern::Free;
    else if (key == "--pattern" && value == "reuse")
      o.pattern = Pattern::Reuse;
    else if (key == "--pattern" && value == "engine")
      o.pattern = Pattern::Engine;
    else if (key == "--sync" && (value == "0" || value == "1"))
      o.sync = value == "1";
    else if (key == "--submissions")
      o.submissions = std::strtoull(value.c_str(), nullptr, 10);
    else if (key == "--labels")
      o.labels = uint32_t(std::strtoul(value.c_str(), nullptr, 10));
    else
      return false;
  }
  return (argc % 2) == 1 && o.submissions > 0;
}

// The labels of one submission: names of a pass name's length (13 characters).
void recordLabels(VkCommandBuffer cmd, uint32_t labels) {
  for (uint32_t k = 0; k < labels; ++k) {
    char name[24];
    std::snprintf(name, sizeof(name), "label_%07u", k);
    VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name;
    vkCmdBeginDebugUtilsLabelEXT(cmd, &label);
    vkCmdEndDebugUtilsLabelEXT(cmd);
  }
}

bool allocate(const engine::Context& ctx, VkCommandBuffer& cmd, VkFence& fence) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  const VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  return vkAllocateCommandBuffers(ctx.device, &alloc, &cmd) == VK_SUCCESS &&
         vkCreateFence(ctx.device, &fenceInfo, nullptr, &fence) == VK_SUCCESS;
}

// Begins `cmd` (which resets it), records the labels, submits it with `fence` (unsignalled) and waits.
bool recordAndSubmit(const engine::Context& ctx, VkCommandBuffer cmd, VkFence fence, uint32_t labels) {
  const VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO, nullptr,
                                       VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, nullptr};
  if (vkBeginCommandBuffer(cmd, &begin) != VK_SUCCESS) return false;
  recordLabels(cmd, labels);
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  return vkEndCommandBuffer(cmd) == VK_SUCCESS && vkQueueSubmit(ctx.queue, 1, &submit, fence) == VK_SUCCESS &&
         vkWaitForFences(ctx.device, 1, &fence, VK_TRUE, UINT64_MAX) == VK_SUCCESS;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: label_stress [--pattern free|reuse|engine] [--submissions N] [--labels L] [--sync 0|1]\n");
    return 2;
  }
  engine::ContextDesc desc;
  desc.validation = true;
  desc.synchronizationValidation = o.sync;
  engine::Context ctx;
  std::string error;
  if (!engine::createContext(desc, ctx, error)) {
    std::fprintf(stderr, "label_stress: %s\n", error.c_str());
    return 1;
  }
  const bool reuse = o.pattern == Pattern::Reuse;
  VkCommandBuffer kept = VK_NULL_HANDLE;
  VkFence keptFence = VK_NULL_HANDLE;
  bool ok = !reuse || allocate(ctx, kept, keptFence);
  for (uint64_t i = 0; i < o.submissions && ok; ++i) {
    if (o.pattern == Pattern::Engine)
      ok = engine::submitAndWait(
          ctx, [&](VkCommandBuffer cmd) { recordLabels(cmd, o.labels); }, error);
    else if (reuse)
      ok = vkResetFences(ctx.device, 1, &keptFence) == VK_SUCCESS && recordAndSubmit(ctx, kept, keptFence, o.labels);
    else {
      VkCommandBuffer cmd = VK_NULL_HANDLE;
      VkFence fence = VK_NULL_HANDLE;
      ok = allocate(ctx, cmd, fence) && recordAndSubmit(ctx, cmd, fence, o.labels);
      vkDestroyFence(ctx.device, fence, nullptr);
      if (cmd) vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &cmd);
    }
    if (i % 10000 == 9999) {  // flushed: a crash loses nothing before it
      std::printf("%llu submissions\n", static_cast<unsigned long long>(i + 1));
      std::fflush(stdout);
    }
  }
  vkDestroyFence(ctx.device, keptFence, nullptr);
  if (kept) vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &kept);
  const uint32_t messages = ctx.validationMessages();
  engine::destroyContext(ctx);
  const char* pattern = o.pattern == Pattern::Free ? "free" : reuse ? "reuse" : "engine";
  std::printf("label_stress: %s, %s, %u validation messages\n", pattern, ok ? "all submitted" : "a call failed",
              messages);
  return ok && messages == 0 ? 0 : 1;
}
