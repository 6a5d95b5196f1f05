// Primary rays that match the raster projection exactly: pixel (x, y) with
// y down, through the pinhole at GpuCamera.position.
#ifndef GI_CAMERA_GLSL
#define GI_CAMERA_GLSL

// `pixel` is continuous: (x + 0.5, y + 0.5) is the centre of pixel (x, y).
vec3 giCameraRayDirection(GpuCamera cam, vec2 pixel) {
  vec2 ndc = pixel / cam.imageSize * 2.0 - 1.0;
  vec3 view = vec3(ndc.x * cam.tanHalfFovY * cam.aspect, -ndc.y * cam.tanHalfFovY, -1.0);
  return normalize(mat3(cam.worldFromView) * view);
}

// Positive distance along the view axis (−Z) of a world point.
float giViewDepth(GpuCamera cam, vec3 world) { return -(cam.viewFromWorld * vec4(world, 1.0)).z; }

#endif
