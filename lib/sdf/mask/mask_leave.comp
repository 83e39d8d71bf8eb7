#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
// MaskLeavePass: before a scroll shifts the coarse refinement state (voxel v takes v + shift's), the band's two counts
// lose the band voxels that leave the grid: one invocation per coarse voxel of the old grid, those that leave and
// whose state says they were in the band at the run that last visited them (kMaskCountCoarse counts exactly those)
// subtract themselves and their fine voxels (maskFineRanges), one atomic per subgroup. The next run over what changed
// (kMaskRegionOnly) then starts from the counts of the voxels that stayed.
#include "sdf/coarse/CoarseParams.h"
#include "sdf/mask/MaskParams.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { MaskLeaveParams params; };
layout(std430, binding = kMaskLeaveBindingCounts) buffer Counts { uint counts[]; };
layout(std430, binding = kMaskLeaveBindingCoarseState) readonly buffer CoarseState { uvec2 coarseState[]; };
layout(std430, binding = kMaskLeaveBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };

void main() {
  ivec3 dims = params.dims.xyz;
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  uint left = 0u, fine = 0u;
  if (i < uint(dims.x * dims.y * dims.z)) {
    ivec3 u = linearCell(i, dims), to = u - params.shift.xyz;
    if ((any(lessThan(to, ivec3(0))) || any(greaterThanEqual(to, dims))) && coarseState[i].x != kNotInBand) {
      ivec2 rx = fineRanges[u.x], ry = fineRanges[dims.x + u.y], rz = fineRanges[dims.x + dims.y + u.z];
      ivec3 n = max(ivec3(rx.y, ry.y, rz.y) - ivec3(rx.x, ry.x, rz.x) + 1, ivec3(0));
      left = 1u;
      fine = uint(n.x * n.y * n.z);
    }
  }
  // Every invocation takes part (none returned early); a difference wraps as two's complement.
  uint leftSum = subgroupAdd(left), fineSum = subgroupAdd(fine);
  if (subgroupElect()) {
    if (leftSum != 0u) atomicAdd(counts[kMaskCountCoarse], 0u - leftSum);
    if (fineSum != 0u) atomicAdd(counts[kMaskCountMaskedFine], 0u - fineSum);
  }
}
