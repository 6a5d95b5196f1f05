#version 460
// Linear-blend skinning (glTF 2.0 §3.7.3): each vertex of a skinned mesh is
// its bind pose transformed by the weighted sum of its four joints' matrices;
// normals by that sum's inverse transpose. Writes the posed vertices the
// engine hands to the GI module (gi::updateMeshVertices, device streams),
// whose scene set 0 the G-buffer's raster reads too.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/skinning.h"

layout(local_size_x = SKINNING_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { SkinningPush pc; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Vec3s { vec3 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) writeonly buffer OutVec3s { vec3 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Uvec4s { uvec4 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Vec4s { vec4 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Mat4s { mat4 v[]; };

uint64_t address(uvec2 a) { return packUint2x32(a); }

void main() {
  if (gl_GlobalInvocationID.x >= pc.count) return;
  const uint vertex = pc.first + gl_GlobalInvocationID.x;
  const uvec4 joints = Uvec4s(address(pc.joints)).v[vertex];
  const vec4 weights = Vec4s(address(pc.weights)).v[vertex];
  Mat4s matrices = Mat4s(address(pc.jointMatrices));
  const mat4 m = weights.x * matrices.v[pc.firstJoint + joints.x] + weights.y * matrices.v[pc.firstJoint + joints.y] +
                 weights.z * matrices.v[pc.firstJoint + joints.z] + weights.w * matrices.v[pc.firstJoint + joints.w];
  const vec3 position = Vec3s(address(pc.bindPositions)).v[vertex];
  const vec3 normal = Vec3s(address(pc.bindNormals)).v[vertex];
  const vec3 n = transpose(inverse(mat3(m))) * normal;
  OutVec3s(address(pc.positions)).v[vertex] = (m * vec4(position, 1.0)).xyz;
  OutVec3s(address(pc.normals)).v[vertex] = dot(n, n) > 0.0 ? normalize(n) : normal;
}
