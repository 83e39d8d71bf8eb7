#version 450
#extension GL_GOOGLE_include_directive : require
// UpsamplePass, one fine voxel per invocation (8 coarse loads each): the baseline `rtsdf bench --suite refine`
// times beside refine_upsample.comp.
#define RTSDF_UPSAMPLE_RUN 1
#include "refine_upsample_main.glsl"
