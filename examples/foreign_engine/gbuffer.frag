#version 460
// The foreign engine's G-buffer: octahedral normals in RG16 unorm, sRGB
// albedo, roughness/metallic in RG8, emission (front faces only), motion in
// pixels. Depth is the hardware reversed-Z buffer.
layout(set = 0, binding = 0) uniform Frame {
  mat4 clipFromWorld;
  mat4 motionClipFromWorld;
  mat4 previousClipFromWorld;
  vec4 cameraPosition;
  vec4 imageSize;
} frame;
layout(push_constant) uniform Draw {
  mat4 worldFromObject;
  vec4 baseColor;
  vec4 emissionRoughness;
  vec4 metallic;
} draw;

layout(location = 0) in vec3 inWorld;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec4 inMotionClip;
layout(location = 3) in vec4 inPreviousClip;
layout(location = 0) out vec2 outNormal;
layout(location = 1) out vec4 outAlbedo;
layout(location = 2) out vec2 outMaterial;
layout(location = 3) out vec4 outEmission;
layout(location = 4) out vec2 outMotion;

vec2 octahedralEncode(vec3 n) {  // unit n → [-1,1]²
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(n.xy, vec2(0.0)));
  return e;
}

void main() {
  // The side facing the camera is shaded; the triangle's own side decides emission.
  vec3 geometric = cross(dFdy(inWorld), dFdx(inWorld));
  float gl = length(geometric);
  vec3 n = normalize(inNormal);
  geometric = gl > 0.0 ? geometric / gl : n;
  if (dot(geometric, n) < 0.0) geometric = -geometric;
  vec3 toCamera = frame.cameraPosition.xyz - inWorld;
  bool front = dot(geometric, toCamera) > 0.0;
  if (!front) n = -n;
  if (dot(n, toCamera) < 0.0) n = front ? geometric : -geometric;

  outNormal = octahedralEncode(n) * 0.5 + 0.5;
  outAlbedo = vec4(draw.baseColor.rgb, 1.0);
  outMaterial = vec2(draw.emissionRoughness.a, draw.metallic.x);
  outEmission = vec4(front ? draw.emissionRoughness.rgb : vec3(0.0), 1.0);
  vec2 current = inMotionClip.xy / inMotionClip.w, previous = inPreviousClip.xy / inPreviousClip.w;
  outMotion = (previous - current) * 0.5 * frame.imageSize.xy;
}
