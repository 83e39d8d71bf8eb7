#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// ClosestRefinePass (refine_main.glsl): exact closest-point distances, one walk per fine voxel; the sign from the
// closest triangle's side (x = 0); for CPU devices such as lavapipe (the BVH walk descends to a leaf before
// testing it).
#include "gpu/shared/Refine.h"
#define RTSDF_REFINE_MODE RTSDF_REFINE_CLOSEST
#define RTSDF_CELL_SEARCH 0
#define RTSDF_SIGN_RAYS 0
#define RTSDF_POINT_WALK_WHILE_WHILE 1
#include "refine_main.glsl"
