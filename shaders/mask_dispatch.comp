#version 450
#extension GL_GOOGLE_include_directive : require
// MaskDispatchPass: one invocation turns the fine voxels MaskCompactPass appended into the refinement's
// indirect dispatch, so the host never reads the mask's size inside the frame.
#include "gpu/shared/Refine.h"

layout(local_size_x = 1) in;
layout(std430, binding = kMaskBindingCounts) buffer Counts { uint counts[]; };

void main() {
  uvec3 groups = refineDispatch(counts[kMaskCountFine]);
  counts[kMaskCountGroupsX] = groups.x;
  counts[kMaskCountGroupsY] = groups.y;
  counts[kMaskCountGroupsZ] = groups.z;
}
