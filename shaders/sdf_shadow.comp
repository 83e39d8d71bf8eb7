#version 450
#extension GL_GOOGLE_include_directive : require
// SdfShadowPass with the fine SDF in a 3D texture: one hardware-filtered (trilinear) fetch per march step.
#include "gpu/shared/RenderBindings.h"
layout(binding = kSdfShadowBindingField) uniform sampler3D fieldTexture;
#define RTSDF_SDF_TEXTURE(uvw) textureLod(fieldTexture, uvw, 0.0).r
#include "sdf_shadow_main.glsl"
