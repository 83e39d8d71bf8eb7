#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// ClosestRefinePass: exact closest-point distances (refine_main.glsl).
#include "gpu/shared/Refine.h"
#define RTSDF_REFINE_MODE RTSDF_REFINE_CLOSEST
#include "refine_main.glsl"
