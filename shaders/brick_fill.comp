#version 450
#extension GL_GOOGLE_include_directive : require
// BrickFillPass: after the refinement, every fine voxel of a slotted brick that is not under the band (|c| > d at
// its coarse slab, or no slab) gets the coarse SDF c_t upsampled, exactly UpsamplePass's value. The pool then holds
// the fine SDF wherever a brick has a slot, and elsewhere the fine SDF is the coarse one upsampled: shading
// samples it without a dense copy. One invocation per voxel of each slot; work grows with the pool, not the grid.
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_BRICK_FILL_GROUP) in;
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kBrickFillBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kBrickFillBindingFineToCoarse) readonly buffer FineToCoarse { int fineToCoarse[]; };
layout(std430, binding = kBrickFillBindingOwners) readonly buffer Owners { uint owners[]; };
#define RTSDF_VALUE_PAGES kBrickFillBindingValuePages
#include "brick_pool.glsl"

#include "coarse_upsample.glsl"

void main() {
  uint k = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint slot = k / kBrickVoxels, local = k % kBrickVoxels;
  if (slot >= uint(params.fineDims.w)) return; // the pool's capacity
  uint b = owners[slot];
  if (b == kNoBrick) return;
  ivec3 bd = params.brickDims.xyz;
  ivec3 brick = ivec3(int(b % uint(bd.x)), int(b / uint(bd.x) % uint(bd.y)), int(b / uint(bd.x * bd.y)));
  ivec3 v = brick * RTSDF_BRICK + ivec3(int(local % 8u), int(local / 8u % 8u), int(local / 64u));
  ivec3 fd = params.fineDims.xyz;
  if (any(greaterThanEqual(v, fd))) return;
  ivec3 c = ivec3(fineToCoarse[v.x], fineToCoarse[fd.x + v.y], fineToCoarse[fd.x + fd.y + v.z]);
  ivec3 cd = params.coarseDims.xyz;
  bool inBand = all(greaterThanEqual(c, ivec3(0))) && abs(coarse[(c.z * cd.y + c.y) * cd.x + c.x]) <= params.band;
  if (!inBand) storeValue(slot, local, upsampleCoarseAt(v));
}
