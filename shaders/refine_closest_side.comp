#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// ClosestRefinePass without sign rays (x = 0): exact closest-point distances, the sign from the closest triangle's
// side (refine_main.glsl). A variant of its own, not a branch on params.rays: a SIMD device such as lavapipe runs
// the ray code, masked, even where no voxel casts a ray.
#include "gpu/shared/Refine.h"
#define RTSDF_REFINE_MODE RTSDF_REFINE_CLOSEST
#define RTSDF_SIGN_RAYS 0
#include "refine_main.glsl"
