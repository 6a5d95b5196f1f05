// Extensions and constants every GI shader uses.
#ifndef GI_COMMON_GLSL
#define GI_COMMON_GLSL
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_nonuniform_qualifier : require

#define GI_PI 3.14159265358979
#define GI_INV_PI 0.318309886183791
#define GI_FLT_MAX 1e30

float giLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
float giMaxComponent(vec3 c) { return max(c.x, max(c.y, c.z)); }
bool giIsFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

#endif
