#version 450
#extension GL_GOOGLE_include_directive : require
// UpsamplePass (refine_upsample.comp, refine_upsample_voxel.comp: this one source compiled with RTSDF_UPSAMPLE_RUN
// from lib/Shaders.cmake's table, RTSDF_UPSAMPLE_RUN_LENGTH or 1): the dense fine SDF after the refinement (which
// writes its values both into the bricks and here, FineStorage::Dense): every fine voxel outside the ray mask
// gets the coarse SDF c_t trilinearly upsampled. Voxels under a band coarse voxel (|c| <= d, found through the
// fine-to-coarse tables: the mask's own slabs) whose brick has a slot are left alone: they hold the refinement's
// value, of this frame or kept from an earlier one; where the brick found no slot (a full pool) they are
// upsampled too. One invocation per run of RTSDF_UPSAMPLE_RUN fine
// voxels along z (neighbouring invocations: neighbouring x, so a group's writes are contiguous): the run keeps
// the 2 x 2 x 2 coarse values of its cell and loads only the new z plane of 4 when it crosses into the next
// coarse cell. The voxels written are those of the region bound (UpsampleRegion: the whole grid).
// With RTSDF_UPSAMPLE_BLOCKS (refine_upsample_blocks.comp, UpsampleByBlocksPass), the fine voxels of the coarse
// blocks UpsampleBlocksPass listed instead: a work group a block, each invocation the runs of its columns along z.
#include "sdf/refine/RefineParams.h"
#ifndef RTSDF_UPSAMPLE_RUN
#error "compile with RTSDF_UPSAMPLE_RUN defined (fine voxels along z per invocation)"
#endif
#ifndef RTSDF_UPSAMPLE_BLOCKS
#define RTSDF_UPSAMPLE_BLOCKS 0
#endif

#if RTSDF_UPSAMPLE_BLOCKS
layout(local_size_x = RTSDF_UPSAMPLE_BLOCK_GROUP, local_size_y = RTSDF_UPSAMPLE_BLOCK_GROUP, local_size_z = 1) in;
#else
layout(local_size_x = RTSDF_UPSAMPLE_GROUP_X, local_size_y = RTSDF_UPSAMPLE_GROUP_Y, local_size_z = 1) in;
#endif
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kUpsampleBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kUpsampleBindingFine) writeonly buffer Fine { float fine[]; };
layout(std430, binding = kUpsampleBindingFineToCoarse) readonly buffer FineToCoarse { int fineToCoarse[]; };
layout(std430, binding = kUpsampleBindingBrickSlots) readonly buffer BrickSlots { uint brickSlots[]; };
#if RTSDF_UPSAMPLE_BLOCKS
layout(std430, binding = kUpsampleBindingBlockList) readonly buffer List { UpsampleBlockListHeader header; uint blocks[]; };
layout(std430, binding = kUpsampleBindingFineBegins) readonly buffer FineBegins { int fineBegins[]; };
#else
layout(std430, binding = kUpsampleBindingRegion) readonly buffer Region { UpsampleRegion region; };
#endif

#include "coarse_upsample.glsl"
#if RTSDF_UPSAMPLE_BLOCKS
#include "upsample_block_fine.glsl"
#endif

// Fine voxels (x, y, zBegin..zEnd - 1) upsampled, but for the slotted band's.
void upsampleRun(int x, int y, int zBegin, int zEnd) {
  ivec3 fd = params.fineDims.xyz;
  ivec3 cd = params.coarseDims.xyz;
  // The coarse row holding this column of fine voxels (the ray mask's slabs), when the band masks anything.
  ivec2 slab = ivec2(fineToCoarse[x], fineToCoarse[fd.x + y]);
  bool maskable = params.band > 0.0 && slab.x >= 0 && slab.y >= 0;
  int plane0 = -1, plane1 = -1;
  vec4 c0 = vec4(0.0), c1 = vec4(0.0); // planes i0.z and i1.z
  for (int z = zBegin; z < zEnd; ++z) {
    ivec3 v = ivec3(x, y, z);
    int slabZ = maskable ? fineToCoarse[fd.x + fd.y + z] : -1;
    if (slabZ >= 0 && abs(coarse[(slabZ * cd.y + slab.y) * cd.x + slab.x]) <= params.band &&
        brickSlots[brickIndexOf(v, params.brickDims.xyz)] != kNoBrick)
      continue;
    ivec3 i0, i1;
    vec3 t;
    upsampleCell(v, i0, i1, t);
    ivec2 x01 = ivec2(i0.x, i1.x), y01 = ivec2(i0.y, i1.y);
    if (i0.z != plane0) {
      c0 = i0.z == plane1 ? c1 : coarsePlane(x01, y01, i0.z);
      plane0 = i0.z;
    }
    if (i1.z != plane1) {
      c1 = i1.z == plane0 ? c0 : coarsePlane(x01, y01, i1.z);
      plane1 = i1.z;
    }
    fine[(v.z * fd.y + v.y) * fd.x + v.x] = trilinear(c0, c1, t);
  }
}

void main() {
#if RTSDF_UPSAMPLE_BLOCKS
  uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (g >= header.groups.w) return;
  ivec3 lo, hi;
  upsampleBlockFine(blocks[g], params.coarseDims.xyz, lo, hi);
  for (int y = lo.y + int(gl_LocalInvocationID.y); y < hi.y; y += RTSDF_UPSAMPLE_BLOCK_GROUP)
    for (int x = lo.x + int(gl_LocalInvocationID.x); x < hi.x; x += RTSDF_UPSAMPLE_BLOCK_GROUP)
      upsampleRun(x, y, lo.z, hi.z);
#else
  ivec3 end = min(region.end.xyz, params.fineDims.xyz);
  int x = region.begin.x + int(gl_GlobalInvocationID.x), y = region.begin.y + int(gl_GlobalInvocationID.y);
  int zBegin = region.begin.z + int(gl_GlobalInvocationID.z) * RTSDF_UPSAMPLE_RUN;
  if (x >= end.x || y >= end.y || zBegin >= end.z) return;
  upsampleRun(x, y, zBegin, min(zBegin + RTSDF_UPSAMPLE_RUN, end.z));
#endif
}
