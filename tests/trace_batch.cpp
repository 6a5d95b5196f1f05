#include "trace_batch.h"

#include <gtest/gtest.h>

#include <cstring>

#include "compute_program.h"
#include "descriptors.h"
#include "trace_batch.comp.compute.h"
#include "trace_batch.comp.h"

namespace oracle {

using namespace engine;  // the engine's resources and programs, which the oracle runs on

std::vector<gpu::TraceBatchResult> traceBatch(const engine::Context& ctx, const engine::SceneGpu& scene,
                                              uint32_t traversal, std::span<const gpu::TraceBatchRay> rays) {
  std::vector<gpu::TraceBatchResult> results(rays.size());
  if (rays.empty()) return results;
  const Binding bindings[] = {{gpu::TB_BINDING_RAYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                              {gpu::TB_BINDING_RESULTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
  std::string error;
  DescriptorSet set = createDescriptorSet(ctx, bindings, error);
  Buffer input =
      createBuffer(ctx, rays.size_bytes(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::HostVisible, error);
  Buffer output = createBuffer(ctx, results.size() * sizeof(gpu::TraceBatchResult), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               MemoryKind::HostVisible, error);
  if (input.mapped) std::memcpy(input.mapped, rays.data(), rays.size_bytes());
  DescriptorWriter(set.set)
      .buffer(gpu::TB_BINDING_RAYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, input.buffer)
      .buffer(gpu::TB_BINDING_RESULTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, output.buffer)
      .write(ctx.vk);
  VkDescriptorSetLayout layouts[] = {scene.set.layout, set.layout};
  ComputeProgram program =
      createComputeProgram(ctx, GI_SCENE_SPIRV(traversal, trace_batch_comp), layouts, sizeof(gpu::TraceBatchPush),
                           {TB_GROUP_SIZE, 1}, error, scene.specialization());
  VkDescriptorSet sets[] = {scene.set.set, set.set};
  submitAndWait(
      ctx,
      [&](VkCommandBuffer cmd) {
        dispatch(ctx, cmd, program, sets, {uint32_t(rays.size()), 1},
                 gpu::TraceBatchPush{uint32_t(rays.size()), 0, 0, 0});
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
      },
      error);
  if (error.empty())
    std::memcpy(results.data(), output.mapped, results.size() * sizeof(gpu::TraceBatchResult));
  else
    ADD_FAILURE() << "the trace-batch oracle: " << error;  // every result stays a miss
  destroyComputeProgram(ctx, program);
  destroyBuffer(ctx, output);
  destroyBuffer(ctx, input);
  destroyDescriptorSet(ctx, set);
  return results;
}

}  // namespace oracle
