#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass, umbra estimate (several marches per pixel and light), the fine SDF in a 3D texture.
#include "gpu/shared/RenderBindings.h"
layout(binding = kSdfShadowBindingField) uniform sampler3D fieldTexture;
#define RTSDF_SDF_TEXTURE(uvw) textureLod(fieldTexture, uvw, 0.0).r
#define RTSDF_SHADOW_UMBRA
#include "sdf_shadow_main.glsl"
