#version 450
#extension GL_GOOGLE_include_directive : require
// MaskDispatchPass: one invocation turns the coarse voxels MaskCompactPass appended to the refine list into the
// refinement's indirect dispatch (refineParts invocations each), so the host never reads the mask's size inside
// the frame, and the stride that spreads its groups over the list on CPU devices (spreadStride, once a frame).
#include "sdf/mask/MaskParams.h"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { MaskParams params; };
layout(std430, binding = kMaskBindingCounts) buffer Counts { uint counts[]; };

void main() {
  // The host refuses grids where every coarse voxel's parts would not fit a uint (refineInvocationLimit).
  uvec3 groups = refineDispatch(counts[kMaskCountRefineList] * uint(params.brickDims.w));
  counts[kMaskCountGroupsX] = groups.x;
  counts[kMaskCountGroupsY] = groups.y;
  counts[kMaskCountGroupsZ] = groups.z;
  counts[kMaskCountSpreadStride] = spreadStride(groups.x * groups.y);
}
