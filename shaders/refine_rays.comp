#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// RayRefinePass: the paper's random rays (refine_main.glsl).
#include "gpu/shared/Refine.h"
#define RTSDF_REFINE_MODE RTSDF_REFINE_RAYS
#include "refine_main.glsl"
