#version 450
#extension GL_GOOGLE_include_directive : require
// UpsamplePass: runs of RTSDF_UPSAMPLE_RUN_LENGTH fine voxels per invocation, about 8 / (fine/coarse ratio)
// coarse loads per fine voxel.
#include "gpu/shared/Refine.h"
#define RTSDF_UPSAMPLE_RUN RTSDF_UPSAMPLE_RUN_LENGTH
#include "refine_upsample_main.glsl"
