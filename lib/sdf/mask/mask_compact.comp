#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// MaskCompactPass: the ray mask on the GPU. One invocation per coarse voxel of the MaskRegion (every voxel, or in a run
// over what changed those whose decision can change: MaskRegionPass): a voxel in the band (|c| <= d, the
// float comparison of the CPU mirror) counts itself and the fine voxels whose centres lie in it (the per-axis range
// tables, computed on the CPU as the mirror does), counts itself in the bricks that hold them (brickBandDelta: the
// sparse fine state; BrickAllocPass gives a slot to a brick whose count is not zero) and, when they are to be refined
// this frame (refinesThisFrame: new to the band, reached by a moving
// instance, not settled), appends itself to the refine list, which the refinement expands into those fine voxels
// (flagged kMaskMovedOnly where the motion alone lists it). The band itself is not listed: a read-back takes it
// from the coarse SDF (SdfPipeline::rayMask(), buildRayMask). A band voxel out of the view's reach (withinViewReach: a cascade
// level above 0) is listed flagged kMaskOutOfView where its fine voxels must take the coarse SDF upsampled again
// (outOfViewRewritten: no walk); it marks no brick, so a brick wholly out of view gives its slot back, and the fine
// voxels of one that straddles the reach's edge hold what the samplers read where there is no slot. A voxel that left
// the band takes the state kNotInBand. A run over what changed keeps the counts of the band and of the bricks and adds
// what its voxels changed, and every run grows the box of the voxels it left settling for the next run's region.
// The refinement hashes by voxel, not by slot, so the list's order does not matter. Slots are reserved per subgroup
// (a ballot's prefix count, one global atomic per counter and subgroup): one global atomic per band voxel serialised the whole band on a single address, and a work
// group's reservation through shared memory needs two barriers, which cost lavapipe as much as the pass's work.
// Compiled with RTSDF_MASK_BLOCK_LIST 1 (mask_compact_blocks.comp, for kMaskBlockList: a run over what changed after a
// scroll) the voxels visited are those of the coarse blocks a list holds (UpsampleBlocksPass's, a work group a block,
// dispatched from the list) instead of the MaskRegion's box: a variant, since lavapipe runs both sides of a branch.
#include "sdf/coarse/CoarseParams.h"
#include "sdf/mask/MaskParams.h"
#include "sdf/refine/RefineParams.h"
#ifndef RTSDF_MASK_BLOCK_LIST
#define RTSDF_MASK_BLOCK_LIST 0
#endif
#if RTSDF_MASK_GROUP != RTSDF_COARSE_BLOCK
#error "a work group of mask_compact.comp must be a coarse block (kMaskBlockList)"
#endif

layout(local_size_x = RTSDF_MASK_GROUP, local_size_y = RTSDF_MASK_GROUP, local_size_z = RTSDF_MASK_GROUP) in;
layout(push_constant) uniform Push { MaskParams params; };
layout(std430, binding = kMaskBindingCounts) buffer Counts { uint counts[]; };
layout(std430, binding = kMaskBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kMaskBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };
layout(std430, binding = kMaskBindingRefineList) writeonly buffer RefineList { uint refineList[]; };
layout(std430, binding = kMaskBindingCoarseState) buffer CoarseState { uvec2 coarseState[]; };
layout(std430, binding = kMaskBindingMovedBoxes) readonly buffer MovedBoxes { MovedBox movedBoxes[]; };
layout(std430, binding = kMaskBindingBrickNeeded) buffer BrickNeeded { uint brickNeeded[]; };
layout(std430, binding = kMaskBindingChangedBox) readonly buffer Changed { uvec4 changedLo; uvec4 changedHi; };
layout(std430, binding = kMaskBindingRegion) buffer Region { MaskRegion region; };
#if RTSDF_MASK_BLOCK_LIST
layout(std430, binding = kMaskBindingBlockList) readonly buffer BlockList {
  UpsampleBlockListHeader listHeader;
  uint listBlocks[];
};
#endif

// Add @a delta to the band counts of the bricks holding fine voxels [lo, hi].
void countBricks(ivec3 lo, ivec3 hi, int delta) {
  ivec3 b0 = lo / RTSDF_BRICK, b1 = hi / RTSDF_BRICK;
  ivec3 bd = params.brickDims.xyz;
  for (int z = b0.z; z <= b1.z; ++z)
    for (int y = b0.y; y <= b1.y; ++y)
      for (int x = b0.x; x <= b1.x; ++x) atomicAdd(brickNeeded[(z * bd.y + y) * bd.x + x], uint(delta));
}

// Grow this run's settling box (frame parity) by @a p: raised atomically only where p lies beyond it as last read.
void growSettling(ivec3 p) {
  uint k = params.frame & 1u;
  for (int a = 0; a < 3; ++a) {
    uint v = uint(p[a]);
    if (v < region.settlingLo[k][a]) atomicMin(region.settlingLo[k][a], v);
    if (v > region.settlingHi[k][a]) atomicMax(region.settlingHi[k][a], v);
  }
}

// Decide whether band voxel p (index i, value c, state before this run @a state) is refined this frame and advance its
// state; sets fresh, and movedOnly where only a moving instance's reach lists it (refinedForMotionAlone). Out of the
// view's reach it is not, and its state says it holds the coarse SDF (no refinements); rewrite: whether its fine voxels
// take that SDF again this frame (outOfViewRewritten). Returns the state after.
uvec2 refineDecision(ivec3 p, uint i, float c, uvec2 state, bool inView, out bool refined, out bool fresh,
                     out bool rewrite, out bool movedOnly) {
  fresh = startsFresh(params, state);
  rewrite = !inView && outOfViewRewritten(params, state, p, changedLo, changedHi);
  movedOnly = false;
  refined = false;
  if (!inView) return uvec2(params.frame, 0u);
  bool nearMoved = false;
  for (uint b = 0u; b < params.movedBoxes && !fresh && !nearMoved; ++b)
    nearMoved = movedWithinReach(params, p, c, movedBoxes[b]);
  refined = refinesThisFrame(params, fresh, nearMoved, state.y, i);
  movedOnly = refinedForMotionAlone(params, fresh, nearMoved, state.y, i);
  return uvec2(params.frame, refinementsAfter(params, refined, fresh, nearMoved, state.y));
}

/// This subgroup's first slot of @a counter for its invocations where @a take, and this invocation's offset from it.
uint reserve(uint counter, bool take, out uint offset) {
  uvec4 ballot = subgroupBallot(take);
  offset = subgroupBallotExclusiveBitCount(ballot);
  uint n = subgroupBallotBitCount(ballot), base = 0u;
  if (subgroupElect() && n > 0u) base = atomicAdd(counts[counter], n);
  return subgroupBroadcastFirst(base);
}

/// Add @a value of every invocation of the subgroup to @a counter (one atomic; a difference wraps as two's complement).
void addSubgroup(uint counter, uint value) {
  uint sum = subgroupAdd(value);
  if (subgroupElect() && sum != 0u) atomicAdd(counts[counter], sum);
}

// The coarse voxel this invocation visits, and whether it lies in the run's region: the MaskRegion's box, or with
// kMaskBlockList this work group's listed block.
ivec3 visitedVoxel(out bool inRegion) {
#if RTSDF_MASK_BLOCK_LIST
  uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  inRegion = g < listHeader.groups.w;
  ivec3 b = inRegion ? linearCell(listBlocks[g], coarseBlockDims(params.coarseDims.xyz)) : ivec3(0);
  ivec3 p = b * RTSDF_COARSE_BLOCK + ivec3(gl_LocalInvocationID);
  inRegion = inRegion && all(lessThan(p, params.coarseDims.xyz));
#else
  ivec3 p = ivec3(gl_GlobalInvocationID) + ivec3(region.lo.xyz);
  inRegion = all(lessThanEqual(p, ivec3(region.hi.xyz)));
#endif
  return p;
}

void main() {
  bool inGrid;
  ivec3 p = visitedVoxel(inGrid);
  ivec3 dims = params.coarseDims.xyz;
  uint i = inGrid ? uint((p.z * dims.y + p.y) * dims.x + p.x) : 0u;
  float c = inGrid ? coarse[i] : 0.0;
  uvec2 state = inGrid ? coarseState[i] : uvec2(kNotInBand);
  bool inBand = inGrid && abs(c) <= params.band;
  bool wasInBand = state.x != kNotInBand;
  bool refined = false, fresh = false, outOfView = false, rewrite = false, movedOnly = false;
  uint count = 0u;
  ivec3 fineLo = ivec3(0), fineHi = ivec3(-1);
  if (inBand || wasInBand) {
    ivec2 rx = fineRanges[p.x], ry = fineRanges[dims.x + p.y], rz = fineRanges[dims.x + dims.y + p.z];
    fineLo = ivec3(rx.x, ry.x, rz.x);
    fineHi = ivec3(rx.y, ry.y, rz.y);
    ivec3 n = max(fineHi - fineLo + 1, ivec3(0));
    count = uint(n.x * n.y * n.z);
  }
  uvec2 after = uvec2(kNotInBand);
  if (inBand) {
    outOfView = !withinViewReach(params, p);
    after = refineDecision(p, i, c, state, !outOfView, refined, fresh, rewrite, movedOnly);
    if (!outOfView && after.y < params.settleFrames) growSettling(p);
  }
  if (inGrid && (inBand || wasInBand)) coarseState[i] = after;
  int bricks = brickBandDelta(params, state, count > 0u, inBand && count > 0u && !outOfView);
  if (bricks != 0) countBricks(fineLo, fineHi, bricks);
  // Every invocation of the subgroup takes part (none returned early).
  uint refineOffset;
  bool listed = refined || rewrite;
  uint baseRefine = reserve(kMaskCountRefineList, listed, refineOffset);
  // The band's counts: from zero, or what changed (kMaskRegionOnly) where a voxel entered or left it.
  bool regionOnly = (params.coarseDims.w & kMaskRegionOnly) != 0;
  uint bandNow = inBand ? 1u : 0u, bandBefore = regionOnly && wasInBand ? 1u : 0u;
  addSubgroup(kMaskCountCoarse, bandNow - bandBefore);
  addSubgroup(kMaskCountMaskedFine, (bandNow - bandBefore) * count);
  addSubgroup(kMaskCountFine, refined ? count : 0u);
  addSubgroup(kMaskCountOutOfView, rewrite ? 1u : 0u);
  uint slot = baseRefine + refineOffset;
  if (listed && slot < params.refineCapacity)
    refineList[slot] = i | (refined && fresh ? kMaskFineFresh : 0u) | (movedOnly ? kMaskMovedOnly : 0u) |
                       (outOfView ? kMaskOutOfView : 0u);
}
