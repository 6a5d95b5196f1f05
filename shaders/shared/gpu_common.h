// Shared between C++ and GLSL: the type aliases that let one struct
// definition serve both sides. GLSL blocks use `scalar` layout, so C++ sizes
// (checked with GPU_ASSERT_SIZE) are the GPU sizes.
#ifndef GI_GPU_COMMON_H
#define GI_GPU_COMMON_H
#include "gpu_macros.h"

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace gpu {
using uint = uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using mat3 = glm::mat3;
using mat4 = glm::mat4;
}  // namespace gpu
#include <algorithm>
#include <cmath>
namespace gpu {
using std::abs;
using std::acos;
using std::ceil;
using std::clamp;
using std::exp2;
using std::floor;
using std::log2;
using std::max;
using std::min;
using std::pow;
using std::sqrt;
using std::uint64_t;
using glm::cross;
using glm::dot;
using glm::normalize;
}  // namespace gpu
#endif

#endif
