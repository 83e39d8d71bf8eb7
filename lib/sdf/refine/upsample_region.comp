#version 450
#extension GL_GOOGLE_include_directive : require
// UpsampleRegionPass: the fine voxels UpsamplePass rewrites after the coarse SDF changed in the box CoarseDistancePass
// grew (upsampleRegionOf), and its indirect work groups. One invocation.
#include "sdf/coarse/CoarseParams.h"
#include "sdf/refine/RefineParams.h"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kUpsampleRegionBindingChanged) readonly buffer Changed { ChangedBox changed; };
layout(std430, binding = kUpsampleRegionBindingRegion) writeonly buffer Region { UpsampleRegion region; };

void main() { region = upsampleRegionOf(changed.lo, changed.hi, params, RTSDF_UPSAMPLE_RUN_LENGTH); }
