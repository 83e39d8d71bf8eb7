#version 450
#extension GL_GOOGLE_include_directive : require
// CoarseRegionPass: the region of a coarse build over what changed (CoarseRegion). GROW, one invocation per block:
// a block that one of the boxes S lies within its bound of the seed distance (coarseBlockReached) is listed, counted
// with its voxels, and its column of blocks listed by the first of its blocks to mark it (the counts and marks zeroed
// by the host; all in the lists' device buffer). DISPATCH, one invocation: the counts copied into the CoarseRegion
// (host memory) with the indirect dispatches of ExactEdtPass's z lines over the listed columns and of
// CoarseDistancePass over the listed blocks.
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_COARSE_REGION_GROUP) in;
layout(push_constant) uniform Push { CoarseRegionParams params; };
layout(std430, binding = kCoarseRegionBindingBlockMax) readonly buffer BlockMax { uint blockMax[]; };
layout(std430, binding = kCoarseRegionBindingRegion) writeonly buffer Region { CoarseRegion region; };
layout(std430, binding = kCoarseRegionBindingLists) buffer Lists { uvec4 counts; uint lists[]; };

uint groupsFor(uint n, uint size) { return (n + size - 1u) / size; }

void writeDispatches() {
  const uint linesPerColumn = uint(RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK);
  region.counts = counts;
  region.edtGroups = uvec4(groupsFor(counts.y * linesPerColumn, RTSDF_EDT_GROUP_X), 1u, 1u, 0u);
  uint groups = groupsFor(counts.x, RTSDF_COARSE_REGION_BLOCKS_PER_GROUP);
  uint rowX = min(groups, kCoarseRegionGroupsX);
  region.distanceGroups = groups == 0u ? uvec4(0u, 1u, 1u, 0u) : uvec4(rowX, groupsFor(groups, rowX), 1u, 0u);
}

void main() {
  ivec3 dims = params.dims.xyz;
  if (params.dims.w == RTSDF_COARSE_REGION_DISPATCH) {
    if (gl_GlobalInvocationID.x == 0u) writeDispatches();
    return;
  }
  ivec3 bd = coarseBlockDims(dims);
  uint b = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (b >= uint(bd.x * bd.y * bd.z)) return;
  ivec3 cell = linearCell(b, bd);
  ivec3 lo = cell * RTSDF_COARSE_BLOCK;
  ivec3 hi = min(lo + ivec3(RTSDF_COARSE_BLOCK - 1), dims - ivec3(1));
  bool reached = false;
  for (int k = 0; k < RTSDF_COARSE_MAX_CHANGES; ++k)
    reached = reached || coarseBlockReached(lo, hi, params.changeLo[k].xyz, params.changeHi[k].xyz, blockMax[b]);
  if (!reached) return;
  // lists[] starts after the counts (word w of the buffer is lists[w - kCoarseRegionCountWords]): the marks first.
  const uint base = kCoarseRegionCountWords;
  lists[coarseRegionBlocksAt(dims) - base + atomicAdd(counts.x, 1u)] = b;
  ivec3 n = hi - lo + ivec3(1);
  atomicAdd(counts.z, uint(n.x * n.y * n.z));
  uint column = uint(cell.y * bd.x + cell.x);
  if (atomicExchange(lists[column], 1u) == 0u)
    lists[coarseRegionColumnsAt(dims) - base + atomicAdd(counts.y, 1u)] = column;
}
