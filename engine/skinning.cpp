#include "skinning.h"

#include <stdexcept>

#include "gi/vk/resources.h"
#include "shared/skinning.h"
#include "skinning.comp.h"

namespace engine {
namespace {

constexpr VkBufferUsageFlags kAddressed =
    VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

glm::uvec2 split(VkDeviceAddress a) { return {uint32_t(a), uint32_t(a >> 32)}; }

}  // namespace

bool createSkinningGpu(const Context& ctx, const Scene& scene, SkinningGpu& out, std::string& error) {
  out = SkinningGpu{};
  const SceneAnimations& a = scene.gltf;
  if (a.skinnedMeshes.empty()) return error.empty();
  out.program =
      createComputeProgram(ctx, spv_skinning_comp, {}, sizeof(gpu::SkinningPush), {SKINNING_GROUP_SIZE, 1}, error);
  out.bindPositions = createBufferFrom(ctx, std::span<const glm::vec3>(a.bindPositions), kAddressed, error);
  out.bindNormals = createBufferFrom(ctx, std::span<const glm::vec3>(a.bindNormals), kAddressed, error);
  out.joints = createBufferFrom(ctx, std::span<const glm::uvec4>(a.vertexJoints), kAddressed, error);
  out.weights = createBufferFrom(ctx, std::span<const glm::vec4>(a.vertexWeights), kAddressed, error);
  size_t joints = 0;
  for (const Skin& s : a.skins) joints += s.joints.size();
  out.jointMatrices = createBuffer(ctx, std::max<size_t>(joints, 1) * sizeof(glm::mat4),
                                   kAddressed | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryKind::DeviceLocal, error);
  out.positions =
      createBuffer(ctx, scene.positions.size() * sizeof(glm::vec3), kAddressed, MemoryKind::DeviceLocal, error);
  out.normals = createBuffer(ctx, scene.normals.size() * sizeof(glm::vec3), kAddressed, MemoryKind::DeviceLocal, error);
  if (!error.empty()) destroySkinningGpu(ctx, out);
  return error.empty();
}

void destroySkinningGpu(const Context& ctx, SkinningGpu& s) {
  if (s.program.pipeline) destroyComputeProgram(ctx, s.program);
  for (Buffer* b :
       {&s.bindPositions, &s.bindNormals, &s.joints, &s.weights, &s.jointMatrices, &s.positions, &s.normals})
    if (b->buffer) destroyBuffer(ctx, *b);
  s = SkinningGpu{};
}

gi::Error recordSkinning(const Context& ctx, VkCommandBuffer cmd, const Scene& scene, SceneGpu& gpu) {
  const SceneAnimations& a = scene.gltf;
  if (a.skinnedMeshes.empty()) return {};
  SkinningGpu& skinning = gpu.skinning;
  const std::vector<glm::mat4>& joints = a.jointMatrices;
  // Earlier frames' reads of the matrices and the posed vertices before this frame's writes.
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_NONE,
                VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  gi::vk::recordBufferWrite(ctx.vk, cmd, skinning.jointMatrices.buffer, skinning.jointMatrices.size, joints.data(),
                            joints.size() * sizeof(glm::mat4));
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  for (const SkinnedMesh& sm : a.skinnedMeshes) {
    const Mesh& mesh = scene.meshes[sm.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
      gpu::SkinningPush push{};
      push.bindPositions = split(skinning.bindPositions.address);
      push.bindNormals = split(skinning.bindNormals.address);
      push.joints = split(skinning.joints.address);
      push.weights = split(skinning.weights.address);
      push.jointMatrices = split(skinning.jointMatrices.address);
      push.positions = split(skinning.positions.address);
      push.normals = split(skinning.normals.address);
      push.first = scene.primitives[p].vertexOffset;
      push.count = scene.primitives[p].vertexCount;
      push.firstJoint = firstJoint(a, sm.skin);
      dispatch(ctx, cmd, skinning.program, {}, {push.count, 1}, push);
    }
  }
  // The posed vertices before the module's decode reads them.
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  gi::MeshVertices vertices;
  vertices.devicePositions = {skinning.positions.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
  vertices.deviceNormals = {skinning.normals.address, VK_FORMAT_R32G32B32_SFLOAT, 0};
  for (const SkinnedMesh& sm : a.skinnedMeshes)
    if (gi::Error e = gi::updateMeshVertices(gpu.scene, cmd, sm.mesh, vertices)) return e;
  return {};
}

}  // namespace engine
