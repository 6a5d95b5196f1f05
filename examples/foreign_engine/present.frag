#version 460
// The engine's own use of a module output: sampled in a fragment shader, in the layout the engine
// keeps it in between frames (gi::ModuleDesc::outputLayout = SHADER_READ_ONLY_OPTIMAL), divided by the
// factor it holds light in (gi::outputScales), into the engine's float target.
layout(set = 0, binding = 0) uniform sampler2D moduleOutput;
layout(push_constant) uniform Present { float inverseScale; } present;
layout(location = 0) out vec4 outRadiance;

void main() {
  outRadiance = vec4(texelFetch(moduleOutput, ivec2(gl_FragCoord.xy), 0).rgb * present.inverseScale, 1.0);
}
