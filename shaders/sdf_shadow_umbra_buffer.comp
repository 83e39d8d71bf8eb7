#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass, umbra estimate (several marches per pixel and light), the fine SDF in a dense storage buffer
// filtered in the shader exactly as the CPU reference filters it.
#include "gpu/shared/RenderBindings.h"
layout(std430, binding = kSdfShadowBindingField) readonly buffer Field { float field[]; };
#define RTSDF_SDF_FETCH(i) field[i]
#define RTSDF_SHADOW_UMBRA
#include "sdf_shadow_main.glsl"
