// Camera matrices for every pass: the raster projection and the ray
// generation in camera.glsl agree pixel for pixel.
#pragma once
#include "gi/gi.h"
#include "scene.h"
#include "shared/gpu_scene.h"

namespace engine {

// `previous` carries last frame's clip transform (for motion vectors); pass
// nullptr on the first frame. The aspect ratio comes from the image, the
// vertical field of view from the camera. `ndcShift` moves the image in
// normalised device coordinates: 2·(jx, jy)/(width, height) for a sub-pixel
// jitter of (jx, jy) pixels (TAA), more for an off-axis projection.
gpu::GpuCamera makeGpuCamera(const Camera& camera, uint32_t width, uint32_t height, const gpu::GpuCamera* previous,
                             glm::vec2 ndcShift = glm::vec2(0.0f));

// The camera as the GI module takes it: plain matrices (gi::CameraDesc).
gi::CameraDesc moduleCamera(const gpu::GpuCamera& camera);

}  // namespace engine
