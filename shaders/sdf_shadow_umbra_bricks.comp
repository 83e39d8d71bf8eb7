#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass, umbra estimate (several marches per pixel and light), the fine SDF sampled from the brick pool
// and the coarse SDF (sdf_shadow_bricks.glsl).
#include "gpu/shared/RenderBindings.h"
#include "sdf_shadow_bricks.glsl"
#define RTSDF_SHADOW_UMBRA
#include "sdf_shadow_main.glsl"
