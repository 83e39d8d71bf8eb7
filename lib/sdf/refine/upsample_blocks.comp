#version 450
#extension GL_GOOGLE_include_directive : require
// UpsampleBlocksPass: the coarse blocks (RTSDF_COARSE_BLOCK^3 voxels) whose fine voxels the upsampling writes again
// after a build over what changed. Listing phase, one invocation per block: a block is listed where a block within one
// of it (itself included) holds a changed voxel that reaches it (the block's mark, or'd by CoarseDistancePass, has the
// bit of the offset back: changedBlockReach), or where it meets a box of UpsampleBoxes grown by a voxel (what a scroll
// invalidated whatever the values). A fine voxel reads the coarse voxels within one of the cell holding its centre,
// so every fine voxel whose upsampled value can differ lies in a listed block. Dispatch phase, one invocation: the
// indirect work groups of refine_upsample_blocks.comp. Its CPU copy is upsampleBlocksCpu (RefineCpu.h).
#include "sdf/refine/RefineParams.h"

layout(local_size_x = RTSDF_UPSAMPLE_BLOCKS_GROUP) in;
layout(push_constant) uniform Push { UpsampleBlocksParams params; };
layout(std430, binding = kUpsampleBlocksBindingMarks) readonly buffer Marks { uint marks[]; };
layout(std430, binding = kUpsampleBlocksBindingBoxes) readonly buffer Boxes { UpsampleBoxes boxes; };
layout(std430, binding = kUpsampleBlocksBindingFineBegins) readonly buffer FineBegins { int fineBegins[]; };
layout(std430, binding = kUpsampleBlocksBindingList) buffer List { UpsampleBlockListHeader header; uint blocks[]; };

bool listed(ivec3 b, ivec3 bd, ivec3 dims) {
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 d = ivec3(dx, dy, dz), n = b + d;
        if (any(lessThan(n, ivec3(0))) || any(greaterThanEqual(n, bd))) continue;
        if ((marks[(n.z * bd.y + n.y) * bd.x + n.x] & changedReachBit(-d)) != 0u) return true;
      }
  for (int k = 0; k < boxes.count.x && k < RTSDF_UPSAMPLE_MAX_BOXES; ++k)
    if (upsampleBlockMeetsBox(b, dims, boxes.lo[k].xyz, boxes.hi[k].xyz)) return true;
  return false;
}

void main() {
  ivec3 dims = params.coarseDims.xyz, bd = coarseBlockDims(dims);
  if (params.coarseDims.w == RTSDF_UPSAMPLE_BLOCKS_DISPATCH) {
    uint n = header.groups.w;
    header.groups.xyz = n == 0u ? uvec3(0u, 1u, 1u)
                                : uvec3(min(n, kCoarseRegionGroupsX), (n + kCoarseRegionGroupsX - 1u) / kCoarseRegionGroupsX, 1u);
    return;
  }
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(RTSDF_UPSAMPLE_BLOCKS_GROUP) +
           gl_LocalInvocationID.x;
  if (i >= uint(bd.x * bd.y * bd.z)) return;
  ivec3 b = linearCell(i, bd);
  if (!listed(b, bd, dims)) return;
  blocks[atomicAdd(header.groups.w, 1u)] = i;
  ivec3 n;
  for (int a = 0; a < 3; ++a) {
    int at = upsampleBlockFineAt(bd, a) + b[a];
    n[a] = fineBegins[at + 1] - fineBegins[at];
  }
  atomicAdd(header.totals.x, uint(n.x * n.y * n.z));
}
