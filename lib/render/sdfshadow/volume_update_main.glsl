#version 450
#extension GL_GOOGLE_include_directive : require
// VolumeUpdatePass (volume_update_blocks.comp, volume_update_refined.comp: this one source compiled with
// RTSDF_VOLUME_UPDATE_REFINED 0 or 1, lib/Shaders.cmake's table): the texels of the fine voxels the last frame of an SdfPipeline wrote into its dense fine SDF
// (DenseFineWrites::Listed), copied from that SDF into the R32F 3D texture SdfShadowPass samples; every other texel
// keeps what it holds, the field's value already (an earlier fill or update). Both dispatches are indirect, from the
// pipeline's own lists on the GPU, so the host reads nothing back and a frame costs what it wrote:
//   blocks (RTSDF_VOLUME_UPDATE_REFINED 0): a work group per block of 4^3 coarse voxels UpsampleBlocksPass listed (the list's header
//   holds the dispatch, as for UpsampleByBlocksPass), the fine voxels of the block (upsampleBlockFineBegins), by
//   columns along z;
//   refined (1): the refinement's dispatch over the mask's refine list (MaskDispatchPass's, at the counts'
//   offset 0, RTSDF_REFINE_GROUP invocations a group), each invocation the box of fine voxels the refinement's
//   invocation of the same index wrote (refinePartBox; WindingExactPass writes only voxels the list holds).
#include "render/sdfshadow/SdfShadowParams.h"

layout(local_size_x = RTSDF_REFINE_GROUP, local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kVolumeUpdateBindingField) readonly buffer Field { float field[]; };
layout(binding = kVolumeUpdateBindingTexture, r32f) uniform writeonly image3D texture;
layout(std430, binding = kVolumeUpdateBindingBlockList) readonly buffer List {
  UpsampleBlockListHeader header;
  uint blocks[];
};
layout(std430, binding = kVolumeUpdateBindingFineBegins) readonly buffer FineBegins { int fineBegins[]; };
layout(std430, binding = kVolumeUpdateBindingRefineList) readonly buffer RefineList { uint refineList[]; };
layout(std430, binding = kVolumeUpdateBindingMaskCounts) readonly buffer MaskCounts { uint maskCounts[]; };
layout(std430, binding = kVolumeUpdateBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };

#include "sdf/refine/upsample_block_fine.glsl"

// Fine voxels lo..hi (inclusive) into the texture.
void copyBox(ivec3 lo, ivec3 hi) {
  ivec3 fd = params.fineDims.xyz;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        imageStore(texture, ivec3(x, y, z), vec4(field[(z * fd.y + y) * fd.x + x], 0.0, 0.0, 0.0));
}

void copyListedBlock() {
  const int side = RTSDF_UPSAMPLE_BLOCK_GROUP; // the invocations as the upsampling's 8 x 8 columns
  uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (g >= header.groups.w || gl_LocalInvocationID.x >= uint(side * side)) return;
  ivec3 lo, end;
  upsampleBlockFine(blocks[g], params.coarseDims.xyz, lo, end);
  int ix = int(gl_LocalInvocationID.x) % side, iy = int(gl_LocalInvocationID.x) / side;
  for (int y = lo.y + iy; y < end.y; y += side)
    for (int x = lo.x + ix; x < end.x; x += side) copyBox(ivec3(x, y, lo.z), ivec3(x, y, end.z - 1));
}

void copyRefinedPart() {
  uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  uint k = g * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  uint parts = params.refineParts;
  uint e = k / parts;
  if (e >= maskCounts[kMaskCountRefineList]) return;
  ivec3 cd = params.coarseDims.xyz;
  ivec3 c = linearCell(refineList[e] & kMaskCoarseIndex, cd);
  ivec3 lo, hi;
  if (refinePartBox(params, fineRanges[c.x], fineRanges[cd.x + c.y], fineRanges[cd.x + cd.y + c.z], k % parts,
                    lo, hi))
    copyBox(lo, hi);
}

void main() {
#if RTSDF_VOLUME_UPDATE_REFINED
  copyRefinedPart();
#else
  copyListedBlock();
#endif
}
