#version 450
#extension GL_GOOGLE_include_directive : require
// The coarse SDF from the nearest seeds: c = |p - seed| * h - beta (the paper's thin negative shells). Each voxel whose
// value differs from the last build's (bit for bit) grows the changed box, so the passes after it can run over the
// region that changed (UpsamplePass). A bound is raised atomically only where this voxel lies beyond it as last read:
// the box only grows, so a stale read costs an atomic, never a voxel left out (no barrier or shared memory, which
// made the pass 4.6 times slower on lavapipe). In a build that keeps its transform, each voxel raises its block's bound
// of the squared seed distance where it exceeds it (coarseBlockReached's input; a full build reset the bounds). A
// build over what changed runs over the CoarseRegion's listed blocks alone, RTSDF_COARSE_REGION_BLOCKS_PER_GROUP a
// group: elsewhere no voxel's nearest seed changed. A voxel whose value changed also marks the blocks its upsampling
// reaches (changedBlockReach, or'd atomically only where a bit is missing as last read: the marks start at zero each
// build), from which UpsampleBlocksPass lists the fine voxels to upsample again.
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { CoarseDistanceParams params; };
layout(std430, binding = kCoarseDistanceBindingNearest) readonly buffer Nearest { uint nearest[]; };
layout(std430, binding = kCoarseDistanceBindingDistance) buffer Distance { float distance[]; };
layout(std430, binding = kCoarseDistanceBindingChanged) buffer Changed { ChangedBox changed; };
layout(std430, binding = kCoarseDistanceBindingBlockMax) buffer BlockMax { uint blockMax[]; };
layout(std430, binding = kCoarseDistanceBindingLists) readonly buffer Lists { uvec4 counts; uint lists[]; };
layout(std430, binding = kCoarseDistanceBindingChangedBlocks) buffer ChangedBlocks { uint changedBlocks[]; };

// The voxel this invocation computes, or false where it computes none.
bool voxelOf(ivec3 dims, out ivec3 p) {
  if ((params.flags & kCoarseDistanceRegionOnly) == 0u) {
    p = ivec3(gl_GlobalInvocationID);
    return all(lessThan(p, dims));
  }
  const uint perBlock = uint(RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK);
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint k = group * uint(RTSDF_COARSE_REGION_BLOCKS_PER_GROUP) + gl_LocalInvocationIndex / perBlock;
  if (k >= counts.x) return false;
  ivec3 bd = coarseBlockDims(dims);
  uint b = lists[coarseRegionBlocksAt(dims) - kCoarseRegionCountWords + k];
  ivec3 local = linearCell(gl_LocalInvocationIndex % perBlock, ivec3(RTSDF_COARSE_BLOCK));
  p = linearCell(b, bd) * RTSDF_COARSE_BLOCK + local;
  return all(lessThan(p, dims));
}

void main() {
  ivec3 dims = params.dims.xyz;
  ivec3 p;
  if (!voxelOf(dims, p)) return;
  int i = (p.z * dims.y + p.y) * dims.x + p.x;
  uint s = nearest[i];
  uint d2 = s == kNoSeed ? 0xFFFFFFFFu : uint(distance2(p, unpackSeed(s)));
  uint block = coarseBlockIndex(p, coarseBlockDims(dims));
  if ((params.flags & kCoarseDistanceKeepBounds) != 0u && d2 > blockMax[block]) atomicMax(blockMax[block], d2);
  float c = s == kNoSeed ? params.emptyDistance : sqrt(float(d2)) * params.voxelSize - params.beta;
  if (floatBitsToUint(distance[i]) != floatBitsToUint(c)) {
    for (int a = 0; a < 3; ++a) {
      uint v = uint(p[a]);
      if (v < changed.lo[a]) atomicMin(changed.lo[a], v);
      if (v > changed.hi[a]) atomicMax(changed.hi[a], v);
    }
    uint reach = changedBlockReach(p % RTSDF_COARSE_BLOCK);
    if ((changedBlocks[block] & reach) != reach) atomicOr(changedBlocks[block], reach);
  }
  distance[i] = c;
}
