#version 450
#extension GL_GOOGLE_include_directive : require
// CoarseRegionPass: the region of a coarse build over what changed (CoarseRegion). GROW, one invocation per block:
// a block that box S lies within its bound of the seed distance (coarseBlockReached) grows the region, raising a
// bound atomically only where the block lies beyond it as last read (as coarse_distance.comp grows its ChangedBox).
// DISPATCH, one invocation: the indirect dispatches of ExactEdtPass's z lines and CoarseDistancePass over the region.
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_COARSE_REGION_GROUP) in;
layout(push_constant) uniform Push { CoarseRegionParams params; };
layout(std430, binding = kCoarseRegionBindingBlockMax) readonly buffer BlockMax { uint blockMax[]; };
layout(std430, binding = kCoarseRegionBindingRegion) buffer Region { CoarseRegion region; };

uint groupsFor(uint n, uint size) { return (n + size - 1u) / size; }

void main() {
  ivec3 dims = params.dims.xyz;
  if (params.dims.w == RTSDF_COARSE_REGION_DISPATCH) {
    if (gl_GlobalInvocationID.x != 0u) return;
    if (region.lo.x > region.hi.x) {
      region.edtGroups = uvec4(0u, 1u, 1u, 0u);
      region.distanceGroups = uvec4(0u, 1u, 1u, 0u);
      return;
    }
    uvec3 n = region.hi.xyz - region.lo.xyz + uvec3(1u);
    region.edtGroups = uvec4(groupsFor(n.x, RTSDF_EDT_GROUP_X), n.y, 1u, 0u);
    region.distanceGroups = uvec4(groupsFor(n.x, RTSDF_JFA_GROUP_X), groupsFor(n.y, RTSDF_JFA_GROUP_Y),
                                  groupsFor(n.z, RTSDF_JFA_GROUP_Z), 0u);
    return;
  }
  ivec3 bd = coarseBlockDims(dims);
  uint b = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (b >= uint(bd.x * bd.y * bd.z)) return;
  ivec3 cell = ivec3(int(b) % bd.x, int(b) / bd.x % bd.y, int(b) / (bd.x * bd.y));
  ivec3 lo = cell * RTSDF_COARSE_BLOCK;
  ivec3 hi = min(lo + ivec3(RTSDF_COARSE_BLOCK - 1), dims - ivec3(1));
  if (!coarseBlockReached(lo, hi, params.changeLo.xyz, params.changeHi.xyz, blockMax[b])) return;
  for (int a = 0; a < 3; ++a) {
    if (uint(lo[a]) < region.lo[a]) atomicMin(region.lo[a], uint(lo[a]));
    if (uint(hi[a]) > region.hi[a]) atomicMax(region.hi[a], uint(hi[a]));
  }
}
