// Interface of gi_scene_gather.comp: decodes one stream of an engine's
// device mesh (vertex attribute or indices, read through its device
// address) into 32-bit words of a host-visible buffer the module reads back
// (floats for attributes, uints for indices).
#ifndef GI_SCENE_GATHER_H
#define GI_SCENE_GATHER_H
#include "gpu_common.h"

GPU_NAMESPACE_BEGIN

#define GATHER_GROUP_SIZE 64u
GPU_CONST GATHER_MAX_GROUPS = 4096u;  // larger streams loop within the dispatch

// Source encodings (gi::DeviceStream formats and index types map onto these
// in gi_module/src/scene/device_meshes.cpp); the output has `components` words.
GPU_CONST GATHER_F32 = 0;        // 32-bit floats (3 or 4 per position or normal, 2 per uv)
GPU_CONST GATHER_F16 = 1;        // half floats, packed two per word
GPU_CONST GATHER_SNORM16 = 2;    // 16-bit signed normalised
GPU_CONST GATHER_UNORM16 = 3;    // 16-bit unsigned normalised
GPU_CONST GATHER_SNORM8 = 4;     // 8-bit signed normalised, four per word
GPU_CONST GATHER_INDEX32 = 5;    // uint32 indices
GPU_CONST GATHER_INDEX16 = 6;    // uint16 indices, two per word (low half first)

struct GatherPush {
  uvec2 source;       // device address of element 0 (low, high 32 bits)
  uvec2 destination;  // device address of the first output word
  uint stride;        // bytes between source elements (index streams: unused)
  uint encoding;      // GATHER_*
  uint count;         // elements
  uint components;    // output words per element (1 for indices)
};
GPU_ASSERT_SIZE(GatherPush, 32);

GPU_NAMESPACE_END

#endif
