// Primary rays that match the raster projection exactly: pixel (x, y) with
// y down, through the pinhole at GpuCamera.position.
#ifndef GI_CAMERA_GLSL
#define GI_CAMERA_GLSL

// giCameraRayDirection(camera, pixel) lives in shared/gpu_scene.h (C++ uses it too).

// Positive distance along the view axis (−Z) of a world point.
float giViewDepth(GpuCamera cam, vec3 world) { return -(cam.viewFromWorld * vec4(world, 1.0)).z; }

#endif
