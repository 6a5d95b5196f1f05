#include "scene/device_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "gi_scene_gather.comp.h"
#include "scene/acceleration.h"
#include "shared/scene_gather.h"

namespace gi {
namespace {

// The formats gi/scene.h accepts per stream: how each decodes and its size.
struct StreamFormat {
  VkFormat format;
  uint32_t encoding;  // gpu::GATHER_*
  uint32_t bytes;
};
constexpr StreamFormat kPositionFormats[] = {
    {VK_FORMAT_R32G32B32_SFLOAT, gpu::GATHER_F32, 12},
    {VK_FORMAT_R32G32B32A32_SFLOAT, gpu::GATHER_F32, 16},
    {VK_FORMAT_R16G16B16A16_SFLOAT, gpu::GATHER_F16, 8},
};
constexpr StreamFormat kNormalFormats[] = {
    {VK_FORMAT_R32G32B32_SFLOAT, gpu::GATHER_F32, 12},   {VK_FORMAT_R32G32B32A32_SFLOAT, gpu::GATHER_F32, 16},
    {VK_FORMAT_R16G16B16A16_SFLOAT, gpu::GATHER_F16, 8}, {VK_FORMAT_R16G16B16A16_SNORM, gpu::GATHER_SNORM16, 8},
    {VK_FORMAT_R8G8B8A8_SNORM, gpu::GATHER_SNORM8, 4},
};
constexpr StreamFormat kUvFormats[] = {
    {VK_FORMAT_R32G32_SFLOAT, gpu::GATHER_F32, 8},
    {VK_FORMAT_R16G16_SFLOAT, gpu::GATHER_F16, 4},
    {VK_FORMAT_R16G16_UNORM, gpu::GATHER_UNORM16, 4},
};

const StreamFormat* findFormat(std::span<const StreamFormat> formats, VkFormat format) {
  for (const StreamFormat& f : formats)
    if (f.format == format) return &f;
  return nullptr;
}

std::string checkStream(const DeviceStream& s, std::span<const StreamFormat> formats, uint32_t vertexCount,
                        const std::string& field) {
  if (!s.address) return field + ".address is 0";
  const StreamFormat* f = findFormat(formats, s.format);
  if (!f) return field + ".format = " + std::to_string(int(s.format)) + " is not one gi/scene.h lists for this stream";
  if (s.address % 4 != 0 || s.stride % 4 != 0)
    return field + ": address and stride must be multiples of 4 bytes (stride " + std::to_string(s.stride) + ")";
  if (s.stride != 0 && s.stride < f->bytes)
    return field + ".stride = " + std::to_string(s.stride) + " is below the format's " + std::to_string(f->bytes) +
           " bytes";
  if (uint64_t(vertexCount) * (s.stride ? s.stride : f->bytes) >= (uint64_t(1) << 32))
    return field + ": the stream spans 4 GiB or more";
  return {};
}

uint32_t strideOf(const DeviceStream& s, std::span<const StreamFormat> formats) {
  return s.stride ? s.stride : findFormat(formats, s.format)->bytes;
}

template <typename T>
std::vector<float> packedCopy(const T* base, uint32_t stride, uint32_t packedBytes, uint32_t count,
                              uint32_t components) {
  std::vector<float> out;
  if (!base) return out;
  out.reserve(size_t(count) * components);
  const uint32_t s = stride ? stride : packedBytes;
  for (uint32_t i = 0; i < count; ++i) {
    const float* e = reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) + size_t(s) * i);
    out.insert(out.end(), e, e + components);
  }
  return out;
}

// Decodes `count` elements from `source` into 32-bit words at `destination`.
void dispatchGather(const vk::Device& d, VkCommandBuffer cmd, const vk::ComputeProgram& gather, VkDeviceAddress source,
                    uint32_t stride, uint32_t encoding, uint32_t count, uint32_t components,
                    VkDeviceAddress destination) {
  if (count == 0) return;
  gpu::GatherPush push{{uint32_t(source), uint32_t(source >> 32)},
                       {uint32_t(destination), uint32_t(destination >> 32)},
                       stride,
                       encoding,
                       count,
                       components};
  const uint32_t groups =
      std::min<uint32_t>((count + GATHER_GROUP_SIZE - 1) / GATHER_GROUP_SIZE, gpu::GATHER_MAX_GROUPS);
  vk::dispatch(d, cmd, gather, {}, {groups * GATHER_GROUP_SIZE, 1}, push);
}

}  // namespace

vk::Status createGatherProgram(const vk::Device& d, vk::ComputeProgram& out) {
  return vk::createComputeProgram(d, spv_gi_scene_gather_comp, {}, sizeof(gpu::GatherPush), {GATHER_GROUP_SIZE, 1}, {},
                                  out);
}

std::string checkVertexStreams(const DeviceStream& positions, const DeviceStream& normals, uint32_t vertexCount,
                               const std::string& where) {
  if (std::string e = checkStream(positions, kPositionFormats, vertexCount, where + ".devicePositions"); !e.empty())
    return e;
  return checkStream(normals, kNormalFormats, vertexCount, where + ".deviceNormals");
}

void recordVertexGather(const vk::Device& d, VkCommandBuffer cmd, const vk::ComputeProgram& gather,
                        const DeviceStream& stream, bool normals, uint32_t first, uint32_t count,
                        VkDeviceAddress destination) {
  std::span<const StreamFormat> formats = normals ? std::span<const StreamFormat>(kNormalFormats) : kPositionFormats;
  const uint32_t stride = strideOf(stream, formats);
  dispatchGather(d, cmd, gather, stream.address + VkDeviceAddress(stride) * first, stride,
                 findFormat(formats, stream.format)->encoding, count, 3, destination);
}

bool isDeviceMesh(const MeshDesc& mesh) { return mesh.device.positions.address != 0; }

std::string checkDeviceMesh(const MeshDesc& mesh, const std::string& where) {
  if (mesh.positions || mesh.normals || mesh.uvs || mesh.indices)
    return where + ": device streams and CPU arrays both given (leave the CPU pointers null)";
  const DeviceMeshDesc& d = mesh.device;
  if (std::string e = checkStream(d.positions, kPositionFormats, mesh.vertexCount, where + ".device.positions");
      !e.empty())
    return e;
  if (std::string e = checkStream(d.normals, kNormalFormats, mesh.vertexCount, where + ".device.normals"); !e.empty())
    return e;
  if (d.uvs.address)
    if (std::string e = checkStream(d.uvs, kUvFormats, mesh.vertexCount, where + ".device.uvs"); !e.empty()) return e;
  if (d.indexType != VK_INDEX_TYPE_UINT32 && d.indexType != VK_INDEX_TYPE_UINT16)
    return where + ".device.indexType = " + std::to_string(int(d.indexType)) + " is not UINT32 or UINT16";
  if (mesh.indexCount > 0 && (!d.indices || d.indices % 4 != 0))
    return where + ".device.indices: a non-zero address, a multiple of 4 bytes, is required with indexCount " +
           std::to_string(mesh.indexCount);
  return {};
}

void holdContents(const SceneContents& c, HeldContents& out) {
  out = HeldContents{};
  for (const MeshDesc& m : c.meshes) {
    out.meshes.push_back(m);
    out.primitives.emplace_back(m.primitives.begin(), m.primitives.end());
    out.positions.push_back(packedCopy(m.positions, m.positionStride, 12, m.vertexCount, 3));
    out.normals.push_back(packedCopy(m.normals, m.normalStride, 12, m.vertexCount, 3));
    out.uvs.push_back(packedCopy(m.uvs, m.uvStride, 8, m.vertexCount, 2));
    out.indices.emplace_back(m.indices ? std::vector<uint32_t>(m.indices, m.indices + m.indexCount)
                                       : std::vector<uint32_t>{});
  }
  out.materials.assign(c.materials.begin(), c.materials.end());
  out.textures.assign(c.textures.begin(), c.textures.end());
  out.lights.assign(c.lights.begin(), c.lights.end());
  out.instances.assign(c.instances.begin(), c.instances.end());
  out.sky = c.sky;
  if (c.sky.map) out.skyMap.assign(c.sky.map, c.sky.map + size_t(c.sky.width) * c.sky.height * c.sky.channels);
}

SceneContents heldView(HeldContents& held) {
  for (size_t m = 0; m < held.meshes.size(); ++m) {
    MeshDesc& d = held.meshes[m];
    d.positions = held.positions[m].empty() ? nullptr : held.positions[m].data();
    d.normals = held.normals[m].empty() ? nullptr : held.normals[m].data();
    d.uvs = held.uvs[m].empty() ? nullptr : held.uvs[m].data();
    d.indices = held.indices[m].empty() ? nullptr : held.indices[m].data();
    d.positionStride = d.normalStride = d.uvStride = 0;
    d.primitives = held.primitives[m];
    d.device = DeviceMeshDesc{};
  }
  held.sky.map = held.skyMap.empty() ? nullptr : held.skyMap.data();
  SceneContents c;
  c.meshes = held.meshes;
  c.materials = held.materials;
  c.textures = held.textures;
  c.lights = held.lights;
  c.instances = held.instances;
  c.sky = held.sky;
  return c;
}

vk::Status recordDeviceMeshReadback(vk::Device& d, VkCommandBuffer cmd, const HeldContents& held,
                                    DeviceMeshReadback& out) {
  size_t words = 0;
  out.meshes.assign(held.meshes.size(), {});
  for (size_t m = 0; m < held.meshes.size(); ++m) {
    const MeshDesc& mesh = held.meshes[m];
    if (!isDeviceMesh(mesh)) continue;
    DeviceMeshReadback::Streams& s = out.meshes[m];
    s.positions = words;
    s.normals = s.positions + size_t(mesh.vertexCount) * 3;
    s.uvs = s.normals + size_t(mesh.vertexCount) * 3;
    s.indices = s.uvs + (mesh.device.uvs.address ? size_t(mesh.vertexCount) * 2 : 0);
    words = s.indices + mesh.indexCount;
  }
  GI_TRY(createGatherProgram(d, out.gather));
  GI_TRY(vk::createBuffer(d, std::max<size_t>(words, 4) * 4,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, true,
                          out.words));
  const VkDeviceAddress base = deviceAddress(d, out.words);
  auto gather = [&](VkDeviceAddress source, uint32_t stride, uint32_t encoding, uint32_t count, uint32_t components,
                    size_t wordOffset) {
    dispatchGather(d, cmd, out.gather, source, stride, encoding, count, components,
                   base + VkDeviceAddress(wordOffset) * 4);
  };
  for (size_t m = 0; m < held.meshes.size(); ++m) {
    const MeshDesc& mesh = held.meshes[m];
    if (!isDeviceMesh(mesh)) continue;
    const DeviceMeshDesc& dev = mesh.device;
    const DeviceMeshReadback::Streams& s = out.meshes[m];
    gather(dev.positions.address, strideOf(dev.positions, kPositionFormats),
           findFormat(kPositionFormats, dev.positions.format)->encoding, mesh.vertexCount, 3, s.positions);
    gather(dev.normals.address, strideOf(dev.normals, kNormalFormats),
           findFormat(kNormalFormats, dev.normals.format)->encoding, mesh.vertexCount, 3, s.normals);
    if (dev.uvs.address)
      gather(dev.uvs.address, strideOf(dev.uvs, kUvFormats), findFormat(kUvFormats, dev.uvs.format)->encoding,
             mesh.vertexCount, 2, s.uvs);
    gather(dev.indices, 0, dev.indexType == VK_INDEX_TYPE_UINT16 ? gpu::GATHER_INDEX16 : gpu::GATHER_INDEX32,
           mesh.indexCount, 1, s.indices);
  }
  vk::memoryBarrier(d, cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  return {};
}

void takeDeviceMeshes(const DeviceMeshReadback& readback, HeldContents& held) {
  const auto* words = static_cast<const uint32_t*>(readback.words.memory.mapped);
  auto floats = [&](size_t offset, size_t count) {
    std::vector<float> v(count);
    if (count) std::memcpy(v.data(), words + offset, count * 4);
    return v;
  };
  for (size_t m = 0; m < held.meshes.size(); ++m) {
    const MeshDesc& mesh = held.meshes[m];
    if (!isDeviceMesh(mesh)) continue;
    const DeviceMeshReadback::Streams& s = readback.meshes[m];
    held.positions[m] = floats(s.positions, size_t(mesh.vertexCount) * 3);
    held.normals[m] = floats(s.normals, size_t(mesh.vertexCount) * 3);
    // Quantised normals come back a little off unit length; zero stays zero (the CPU checks name it).
    // 32-bit floats stay as the engine wrote them, as CPU arrays do: normalised twice, a normal differed
    // from the CPU array's in its last bit, and an H200's shading moved a pixel by 9e-4 with it.
    const bool quantised = mesh.device.normals.format != VK_FORMAT_R32G32B32_SFLOAT &&
                           mesh.device.normals.format != VK_FORMAT_R32G32B32A32_SFLOAT;
    for (size_t v = 0; quantised && v < mesh.vertexCount; ++v) {
      float* n = &held.normals[m][3 * v];
      const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (length > 0.0f && std::isfinite(length))
        for (int k = 0; k < 3; ++k) n[k] /= length;
    }
    held.uvs[m] = mesh.device.uvs.address ? floats(s.uvs, size_t(mesh.vertexCount) * 2) : std::vector<float>{};
    held.indices[m].assign(words + s.indices, words + s.indices + mesh.indexCount);
  }
}

void destroyDeviceMeshReadback(vk::Device& d, DeviceMeshReadback& readback) {
  vk::destroyComputeProgram(d, readback.gather);
  vk::destroyBuffer(d, readback.words);
  readback = DeviceMeshReadback{};
}

}  // namespace gi
