#version 460
// The filters' guidance from the G-buffer: normal scaled to [0,1] and view
// depth divided by a fixed scene-derived constant (guidance, shared/gi_filters.h),
// and position relative to the camera with view depth, over the same constant
// (position). Both images are half floats: over the scene extent the values
// stay within about ±1 at any scene scale, and the filters use positions only
// through differences and their ratio to the view depth. The guidance's depth is 0
// exactly for background: gif and bilateral take coverage from it and hold no
// positions (GiGuidancePush::positions).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "gi_frame.glsl"

layout(local_size_x = GI_GROUP_SIZE, local_size_y = GI_GROUP_SIZE) in;
layout(push_constant, scalar) uniform Push { GiGuidancePush pc; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!giInFrame(gl_GlobalInvocationID.xy)) return;
  if (!giGbCovered(p)) {
    imageStore(giGuidance, p, vec4(0.5, 0.5, 0.5, 0.0));
    if (pc.positions != 0u) imageStore(giPosition, p, vec4(0.0));
    return;
  }
  vec3 n = giGbNormal(p);
  float viewZ = giGbViewDepth(p);
  vec3 dir;
  vec3 position = giGbPosition(p, dir);
  imageStore(giGuidance, p, vec4(n * 0.5 + 0.5, viewZ / giFrame.depthScale));
  if (pc.positions != 0u)
    imageStore(giPosition, p, vec4(position - giFrame.camera.position, viewZ) / giFrame.depthScale);
}
