#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass with the fine SDF sampled from the brick pool (the sparse fine state) and the coarse SDF, filtered
// in the shader exactly as the CPU reference filters a dense field (8 fetches per march step).
#include "gpu/shared/RenderBindings.h"
#include "sdf_shadow_bricks.glsl"
#include "sdf_shadow_main.glsl"
