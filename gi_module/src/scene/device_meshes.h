// Meshes in the engine's device buffers (gi::DeviceMeshDesc): checked,
// decoded by gi_scene_gather.comp into a host-visible buffer, and, once that
// completed, turned back into CPU meshes for the usual build. The scene's
// contents are held by the module meanwhile (the engine's arrays may be
// freed once createScene returns).
#pragma once
#include <string>
#include <vector>

#include "gi/scene.h"
#include "gi/vk/programs.h"
#include "gi/vk/resources.h"

namespace gi {

bool isDeviceMesh(const MeshDesc& mesh);
// The stream formats, strides and addresses of a device mesh; "" when good.
std::string checkDeviceMesh(const MeshDesc& mesh, const std::string& where);

// A copy of SceneContents that owns every array (device meshes keep their
// descriptions; their data arrives with the read-back).
struct HeldContents {
  std::vector<MeshDesc> meshes;
  std::vector<std::vector<PrimitiveDesc>> primitives;
  std::vector<std::vector<float>> positions, normals,
      uvs;  // per mesh, packed (CPU meshes copied; device meshes read back)
  std::vector<std::vector<uint32_t>> indices;
  std::vector<MaterialDesc> materials;
  std::vector<TextureDesc> textures;
  std::vector<LightDesc> lights;
  std::vector<InstanceDesc> instances;
  SkyDesc sky;
  std::vector<float> skyMap;
};
void holdContents(const SceneContents& contents, HeldContents& out);
// A view of `held` whose meshes are all CPU arrays (after the read-back).
SceneContents heldView(HeldContents& held);

struct DeviceMeshReadback {
  vk::ComputeProgram gather;
  vk::Buffer words;  // host-visible: every device mesh's streams, decoded
  struct Streams {
    size_t positions = 0, normals = 0, uvs = 0, indices = 0;  // word offsets
  };
  std::vector<Streams> meshes;  // per mesh of the contents (unused for CPU meshes)
};
// Records the decode of every device mesh of `held` into `cmd`, ending with
// a barrier that makes the words visible to the host.
vk::Status recordDeviceMeshReadback(vk::Device& device, VkCommandBuffer cmd, const HeldContents& held,
                                    DeviceMeshReadback& out);
// After `cmd` completed: the decoded streams into `held`'s arrays (normals normalised).
void takeDeviceMeshes(const DeviceMeshReadback& readback, HeldContents& held);
void destroyDeviceMeshReadback(vk::Device& device, DeviceMeshReadback& readback);

// gi_scene_gather.comp, for the read-back and for gi::updateMeshVertices's device streams.
vk::Status createGatherProgram(const vk::Device& device, vk::ComputeProgram& out);
// gi::MeshVertices's device streams (`where` names the argument); "" when good.
std::string checkVertexStreams(const DeviceStream& positions, const DeviceStream& normals, uint32_t vertexCount,
                               const std::string& where);
// Records the decode of elements [first, first + count) of a position (normals false) or normal stream into
// packed floats, three per element, at `destination` (normals as stored: the shaders normalise them).
void recordVertexGather(const vk::Device& device, VkCommandBuffer cmd, const vk::ComputeProgram& gather,
                        const DeviceStream& stream, bool normals, uint32_t first, uint32_t count,
                        VkDeviceAddress destination);

}  // namespace gi
