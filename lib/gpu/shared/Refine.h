// Shared by C++ and GLSL: the fine-SDF refinement's parameters, its random numbers (PCG hash, identical
// integer arithmetic on both sides) and the state it keeps per fine voxel.
#ifndef RTSDF_GPU_SHARED_REFINE_H
#define RTSDF_GPU_SHARED_REFINE_H
#include "gpu/shared/Bvh.h"

RTSDF_SHARED_BEGIN

/// Refinement modes: the shaders refine_rays.comp and refine_closest.comp are refine_main.glsl compiled with
/// RTSDF_REFINE_MODE set to one of these.
#define RTSDF_REFINE_RAYS 0    // the paper: x random rays per voxel per frame, nearest hit, decayed history
#define RTSDF_REFINE_CLOSEST 1 // exact closest-point distance through the same BVH, deterministic

/// Work-group shape of refine_upsample.comp (x fastest in memory; one invocation per run along z).
#define RTSDF_UPSAMPLE_GROUP_X 32
#define RTSDF_UPSAMPLE_GROUP_Y 2
/// Fine voxels along z per invocation of refine_upsample.comp.
#define RTSDF_UPSAMPLE_RUN_LENGTH 16
/// Work-group size of the refinement shaders (one invocation per masked fine voxel).
#define RTSDF_REFINE_GROUP 64

/// Bindings of refine_upsample.comp.
const uint kUpsampleBindingCoarse = 0u;       // coarse SDF c_t (read)
const uint kUpsampleBindingFine = 1u;         // fine SDF: c_t upsampled, written outside the ray mask
const uint kUpsampleBindingFineToCoarse = 2u; // int per fine index per axis (x entries, then y, then z): the coarse
                                              // voxel whose slab holds it (maskCoarseOfFine), -1: none
const uint kUpsampleBindingCount = 3u;

/// Work-group shape of mask_compact.comp (one invocation per coarse voxel).
#define RTSDF_MASK_GROUP 4

/// Bindings of mask_compact.comp (MaskCompactPass) and mask_dispatch.comp (MaskDispatchPass, counts only).
const uint kMaskBindingCounts = 0u;      // MaskCounts words: the refinement's indirect dispatch, then the counters
const uint kMaskBindingCoarse = 1u;      // coarse SDF c_t (read)
const uint kMaskBindingFineRanges = 2u;  // ivec2 per coarse index per axis (x entries, then y, then z): the fine
                                         // voxels [lo, hi] whose centres lie in that coarse slab
const uint kMaskBindingFineList = 3u;    // appended: the fine voxels to refine, packed (kMaskFine*), in no order
const uint kMaskBindingCoarseList = 4u;  // appended: (coarse linear index, floatBitsToUint(c)) per band voxel
const uint kMaskBindingCoarseState = 5u; // uvec2 per coarse voxel: (last frame in the band, refinements in a row)
const uint kMaskBindingMovedBoxes = 6u;  // MovedBox per instance that moved since the previous frame
const uint kMaskBindingCount = 7u;

/// A fine-list entry: x | y << 10 | z << 20, and kMaskFineFresh when the voxel is new to the mask (no history).
const uint kMaskFineCoords = 0x3FFFFFFFu;
const uint kMaskFineFresh = 0x40000000u;

/// Word indices of the counts buffer: a VkDispatchIndirectCommand for the refinement at offset 0, then the
/// counters mask_compact.comp appends with (reset to 0 before it runs).
const uint kMaskCountGroupsX = 0u;
const uint kMaskCountGroupsY = 1u;
const uint kMaskCountGroupsZ = 2u;
const uint kMaskCountFine = 3u;       // fine voxels appended: those refined this frame
const uint kMaskCountCoarse = 4u;     // coarse band voxels appended
const uint kMaskCountMaskedFine = 5u; // fine voxels under the band, refined or kept
const uint kMaskCountWords = 8u;

/// Moving instances' boxes MaskCompactPass reads (more are merged into the last one).
#define RTSDF_MAX_MOVED_BOXES 256

/// The box an instance swept from the previous frame to this one: the union of its world bounds in both poses,
/// in the frame the GPU passes measure from (w unused).
struct MovedBox {
  vec4 lo;
  vec4 hi;
};

/// Push constants of mask_compact.comp and mask_dispatch.comp.
struct MaskParams {
  ivec4 coarseDims;    // xyz: coarse voxels per axis
  float band;          // d: a coarse voxel is in the band when |c| <= d (the CPU mirror's float comparison)
  uint fineCapacity;   // entries the fine list holds (appends beyond it are counted, not written)
  uint coarseCapacity; // entries the coarse list holds
  uint frame;          // frame number (1, 2, ...)
  vec4 coarseOriginH;  // xyz: corner of coarse voxel (0,0,0) in the GPU's frame, w: coarse voxel size
  float reachPad;      // a fine voxel of the cell is within |c| + reachPad of the surface (see movedWithinReach)
  uint settleFrames;   // refinements in a row after which a voxel is settled; 0: refine every band voxel
  uint refreshPeriod;  // a settled voxel is refined again once every this many frames; 0: never
  uint movedBoxes;     // MovedBox entries this frame
};

/// Incremental refinement, decided per coarse band voxel for all the fine voxels under it: whether they are
/// refined this frame (else they keep their values). They are when every band voxel is (settleFrames == 0), when
/// the voxel is new to the band (@a fresh), when a moving instance came within reach (@a nearMoved), while it has
/// had fewer than settleFrames refinements in a row, and, settled, once every refreshPeriod frames (staggered by
/// the coarse index @a voxel).
RTSDF_FN bool refinesThisFrame(MaskParams p, bool fresh, bool nearMoved, uint refinements, uint voxel) {
  if (p.settleFrames == 0u || fresh || nearMoved || refinements < p.settleFrames) return true;
  return p.refreshPeriod != 0u && (voxel + p.frame) % p.refreshPeriod == 0u;
}

/// The voxel's refinements in a row after this frame: restarted by entering the band or a moving instance,
/// counted up while refined (saturating), unchanged while kept.
RTSDF_FN uint refinementsAfter(bool refined, bool fresh, bool nearMoved, uint refinements) {
  if (!refined) return refinements;
  if (fresh || nearMoved) return 1u;
  return refinements == 0xFFFFFFFFu ? refinements : refinements + 1u;
}

/// Whether moving box @a b lies within reach of coarse voxel @a v, whose value is @a c. Every fine voxel centre
/// in the cell is within R = |c| + reachPad of the surface (the nearest seed touches it within half a coarse
/// diagonal, c took beta off, and a fine centre is within half a diagonal of the coarse centre; reachPad adds
/// a fine voxel for rounding). If the distance at such a point changed, a moving instance is within R of it in
/// one of its poses: it came nearer than the old distance, so within the new one (<= R), or it was the nearest
/// and moved off, so the old distance was below the new one (<= R).
RTSDF_FN bool movedWithinReach(MaskParams p, ivec3 v, float c, MovedBox b) {
  RTSDF_PRECISE vec3 lo = vec3(p.coarseOriginH) + vec3(v) * p.coarseOriginH.w;
  RTSDF_PRECISE vec3 hi = lo + vec3(p.coarseOriginH.w);
  RTSDF_PRECISE vec3 gap = max(max(vec3(b.lo) - hi, lo - vec3(b.hi)), vec3(0.0));
  RTSDF_PRECISE float reach = abs(c) + p.reachPad;
  return dot(gap, gap) <= reach * reach;
}

/// The indirect dispatch of @a fineVoxels voxels in groups of RTSDF_REFINE_GROUP: at most 65535 groups along
/// x, the rest along y (the refinement flattens them); no groups at all for an empty mask.
RTSDF_FN uvec3 refineDispatch(uint fineVoxels) {
  uint groups = fineVoxels / uint(RTSDF_REFINE_GROUP) + (fineVoxels % uint(RTSDF_REFINE_GROUP) != 0u ? 1u : 0u);
  if (groups == 0u) return uvec3(0u, 0u, 1u);
  uint gx = min(groups, 65535u);
  return uvec3(gx, (groups + gx - 1u) / gx, 1u);
}

/// Bindings of refine_rays.comp and refine_closest.comp: the scene BVH (Bvh.h's kBvhBinding*), then these.
const uint kRefineBindingMask = kBvhBindingCount + 0u;       // the fine voxels to refine (MaskCompactPass's list)
const uint kRefineBindingFine = kBvhBindingCount + 1u;       // in: f_{t-1} signed (not fresh); out: f_t signed
const uint kRefineBindingVotes = kBvhBindingCount + 2u;      // decayed (front, back) hits, two halves
const uint kRefineBindingMaskCounts = kBvhBindingCount + 3u; // MaskCounts words: the list's size at kMaskCountFine
const uint kRefineBindingCoarse = kBvhBindingCount + 4u;     // coarse SDF c_t (upsampled for the bound)
const uint kRefineBindingCount = kBvhBindingCount + 5u;

/// Push constants of refine_upsample.comp and the refinement shaders.
struct RefineParams {
  vec4 fineOriginH;      // xyz: world corner of fine voxel (0,0,0), w: fine voxel size
  ivec4 fineDims;        // xyz: fine voxels per axis, w: unused (the mask's size is read on the GPU)
  vec4 coarseOriginInvH; // xyz: world corner of coarse voxel (0,0,0), w: 1 / coarse voxel size
  ivec4 coarseDims;      // xyz: coarse voxels per axis
  float alpha;           // history decay
  uint rays;             // x, rays per masked voxel per frame
  uint frame;            // frame number (1, 2, ...)
  uint seed;             // per-run random seed
  float beta;            // the coarse shell (closest mode widens its search by it)
  float band;            // upsample: > 0 leaves the fine voxels under band coarse voxels (|c| <= d) alone
  uint pad0, pad1;
};

/// The two uniform numbers in [0, 1) of ray @a ray of voxel @a voxel in frame @a frame.
RTSDF_FN uint rayHash(uint voxel, uint frame, uint ray, uint seed) {
  return pcgHash(voxel ^ pcgHash(frame * 0x9E3779B9u + pcgHash(ray + seed * 0x85EBCA6Bu)));
}

RTSDF_SHARED_END

#endif
