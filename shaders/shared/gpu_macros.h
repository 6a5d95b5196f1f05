// Shared between C++ and GLSL: the macros that let one declaration serve both sides (constants, sizes
// checked against GLSL's scalar layout, functions, out parameters). No GLM: the module's public header
// reaches this file (through scene_modes.h), so it needs nothing beyond the standard library.
#ifndef GI_GPU_MACROS_H
#define GI_GPU_MACROS_H

#ifdef __cplusplus
#include <cstdint>
namespace gpu {
using uint = uint32_t;
}  // namespace gpu
#define GPU_NAMESPACE_BEGIN namespace gpu {
#define GPU_NAMESPACE_END }
#define GPU_ASSERT_SIZE(T, bytes) static_assert(sizeof(T) == (bytes), #T " must match its GLSL scalar layout")
#define GPU_CONST inline constexpr uint
#define GPU_FN inline
#define GPU_OUT(T) T&  // an out parameter: `out T` in GLSL
#else
#define GPU_NAMESPACE_BEGIN
#define GPU_NAMESPACE_END
#define GPU_ASSERT_SIZE(T, bytes)
#define GPU_CONST const uint
#define GPU_FN
#define GPU_OUT(T) out T
#endif

#endif
