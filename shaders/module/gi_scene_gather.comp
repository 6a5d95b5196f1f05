#version 460
// Decodes one stream of an engine's device mesh into 32-bit words for the
// module to read back (gi::createScene with DeviceMeshDesc): attributes as
// floats, indices as uints. Sources are read as aligned 32-bit words through
// their device address (gi/scene.h: addresses and strides are multiples of 4).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/scene_gather.h"

layout(local_size_x = GATHER_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GatherPush pc; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Word { uint value; };
layout(buffer_reference, scalar, buffer_reference_align = 4) writeonly buffer Words { uint values[]; };

uint loadWord(uint64_t address) { return Word(address).value; }

// Component k of the element starting at `address`.
float decode(uint64_t address, uint k) {
  switch (pc.encoding) {
    case GATHER_F32: return uintBitsToFloat(loadWord(address + 4ul * k));
    case GATHER_F16: return unpackHalf2x16(loadWord(address + 4ul * (k / 2u)))[k % 2u];
    case GATHER_SNORM16: return unpackSnorm2x16(loadWord(address + 4ul * (k / 2u)))[k % 2u];
    case GATHER_UNORM16: return unpackUnorm2x16(loadWord(address + 4ul * (k / 2u)))[k % 2u];
    default: return unpackSnorm4x8(loadWord(address))[k];  // GATHER_SNORM8
  }
}

void main() {
  const uint64_t source = packUint2x32(pc.source);
  Words out_ = Words(packUint2x32(pc.destination));
  const uint step = gl_NumWorkGroups.x * GATHER_GROUP_SIZE;
  for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += step) {
    if (pc.encoding == GATHER_INDEX32) {
      out_.values[i] = loadWord(source + 4ul * i);
    } else if (pc.encoding == GATHER_INDEX16) {
      out_.values[i] = (loadWord(source + 4ul * (i / 2u)) >> (16u * (i % 2u))) & 0xffffu;
    } else {
      const uint64_t element = source + uint64_t(pc.stride) * i;
      for (uint k = 0u; k < pc.components; ++k) out_.values[i * pc.components + k] = floatBitsToUint(decode(element, k));
    }
  }
}
