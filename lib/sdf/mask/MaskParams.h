// Shared by C++ and GLSL: the ray mask's and the brick pool's parameters, bindings and decisions: mask_compact.comp
// (MaskCompactPass), mask_dispatch.comp (MaskDispatchPass), brick_alloc.comp (BrickAllocPass) and their CPU copies
// (MaskCpu.h) call the very same functions. The refinement (sdf/refine/RefineParams.h) reads the pool they keep.
#ifndef RTSDF_SDF_MASK_MASKPARAMS_H
#define RTSDF_SDF_MASK_MASKPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// The sparse fine state: the fine grid is cut into bricks of RTSDF_BRICK^3 voxels; only bricks under the ray
/// mask hold a slot of the brick pool, where the refinement keeps its values (the history) and sign votes.
#define RTSDF_BRICK 8
const uint kBrickVoxels = 512u;        // RTSDF_BRICK^3
const uint kNoBrick = 0xFFFFFFFFu;     // a brick without a slot
/// The pool is split into pages of pageBricks bricks, one storage buffer each (a single buffer is bounded by
/// maxStorageBufferRange: 128 MiB on lavapipe, 65536 bricks of floats).
#define RTSDF_BRICK_PAGES 4
/// Work-group size of brick_alloc.comp (one invocation per brick).
#define RTSDF_BRICK_GROUP 64

/// Word indices of the brick counts buffer (BrickAllocPass). kBrickCountFreeTop persists from frame to frame;
/// the others are reset to 0 before each frame's allocation.
const uint kBrickCountFreeTop = 0u;   // slots on the free stack
const uint kBrickCountActive = 1u;    // bricks under the ray mask this frame
const uint kBrickCountAllocated = 2u; // slots taken from the free stack this frame (or asked for beyond it)
const uint kBrickCountOverflow = 3u;  // bricks under the ray mask left without a slot (the pool was full)
const uint kBrickCountWords = 4u;

/// Bindings of brick_alloc.comp.
const uint kBrickBindingCounts = 0u; // kBrickCount* words
const uint kBrickBindingNeeded = 1u; // uint per brick: the band voxels in view over it (MaskCompactPass)
const uint kBrickBindingSlots = 2u;  // uint per brick: its slot, kNoBrick: none
const uint kBrickBindingFree = 3u;   // the free stack of slots, kBrickCountFreeTop of them
const uint kBrickBindingCount = 4u;

/// Push constants of brick_alloc.comp.
struct BrickParams {
  uint bricks; // bricks in the grid
  uint phase;  // RTSDF_BRICK_FREE, RTSDF_BRICK_TAKE or RTSDF_BRICK_SETTLE
  uint pad0, pad1;
};
#define RTSDF_BRICK_FREE 0u   // per brick: a slot whose brick no band voxel in view counts in goes back on the stack
#define RTSDF_BRICK_TAKE 1u   // per brick: a needed brick without a slot takes one off the stack (or overflows)
#define RTSDF_BRICK_SETTLE 2u // one invocation: the stack's top lowered by the slots taken

/// The brick holding fine voxel @a v (bricks x fastest, @a brickDims per axis), and @a v's place in it.
RTSDF_FN uint brickIndexOf(ivec3 v, ivec3 brickDims) {
  ivec3 b = v / RTSDF_BRICK;
  return uint((b.z * brickDims.y + b.y) * brickDims.x + b.x);
}
RTSDF_FN uint brickLocalOf(ivec3 v) {
  ivec3 l = v % RTSDF_BRICK;
  return uint((l.z * RTSDF_BRICK + l.y) * RTSDF_BRICK + l.x);
}

/// Work-group size of the refinement shaders (one invocation per box of fine voxels under a listed coarse voxel).
#define RTSDF_REFINE_GROUP 64

/// Work-group shape of mask_compact.comp (one invocation per coarse voxel).
#define RTSDF_MASK_GROUP 4

/// Bindings of mask_compact.comp (MaskCompactPass) and mask_dispatch.comp (MaskDispatchPass, counts only).
const uint kMaskBindingCounts = 0u;      // MaskCounts words: the refinement's indirect dispatch, then the counters
const uint kMaskBindingCoarse = 1u;      // coarse SDF c_t (read)
const uint kMaskBindingFineRanges = 2u;  // ivec2 per coarse index per axis (x entries, then y, then z): the fine
                                         // voxels [lo, hi] whose centres lie in that coarse slab
const uint kMaskBindingRefineList = 3u;  // appended: the coarse voxels whose fine voxels are refined this frame,
                                         // linear index | kMaskFineFresh when new to the band | kMaskMovedOnly |
                                         // kMaskOutOfView, in no order
const uint kMaskBindingCoarseState = 4u; // uvec2 per coarse voxel: (the run that last visited it in the band, or
                                         // kNotInBand; refinements in a row)
const uint kMaskBindingMovedBoxes = 5u;  // MovedBox per instance that moved since the previous frame
const uint kMaskBindingBrickNeeded = 6u; // uint per brick: the band voxels in view over it (counted: brickBandDelta)
const uint kMaskBindingChangedBox = 7u;  // the coarse SDF's ChangedBox (read where kMaskCoarseRebuilt)
const uint kMaskBindingRegion = 8u;      // MaskRegion: the voxels visited (read), the settling box (grown)
const uint kMaskBindingBlockList = 9u;   // with kMaskBlockList: the coarse blocks visited (UpsampleBlocksPass's list)
const uint kMaskBindingCount = 10u;

/// Bindings of mask_leave.comp (MaskLeavePass).
const uint kMaskLeaveBindingCounts = 0u;      // MaskCounts words: the band's two counts lowered
const uint kMaskLeaveBindingCoarseState = 1u; // the coarse state before the scroll's shift (read)
const uint kMaskLeaveBindingFineRanges = 2u;  // maskFineRanges of the grids
const uint kMaskLeaveBindingCount = 3u;
/// Push constants of mask_leave.comp: the coarse grid's dims and the scroll's shift (voxel v takes v + shift's).
struct MaskLeaveParams {
  ivec4 dims;
  ivec4 shift;
};

/// Bindings of mask_region.comp (MaskRegionPass).
const uint kMaskRegionBindingChangedBox = 0u; // the coarse SDF's ChangedBox (read where kMaskCoarseRebuilt)
const uint kMaskRegionBindingRegion = 1u;     // MaskRegion (written; the settling boxes read and reset)
const uint kMaskRegionBindingCount = 2u;

/// A coarse voxel's state before it has been in the band, and after it left (both words).
const uint kNotInBand = 0xFFFFFFFFu;

/// The coarse voxels one run of MaskCompactPass visits (MaskRegionPass): all of them, or where a run over what changed
/// (kMaskRegionOnly) may decide otherwise than the last: where the coarse SDF changed, where a moving box comes within
/// the band's reach, and where band voxels were left settling. lo and hi inclusive, empty while lo.x > hi.x; groups:
/// the indirect dispatch over them. settlingLo/Hi[k]: the box of the band voxels that the run of a frame number of
/// parity k left with fewer than settleFrames refinements (grown by that run, reset by the region pass before it).
struct MaskRegion {
  uvec4 lo;
  uvec4 hi;
  uvec4 groups;
  uvec4 pad0;
  uvec4 settlingLo[2];
  uvec4 settlingHi[2];
};

/// Push constants of mask_region.comp.
struct MaskRegionParams {
  ivec4 dims;   // xyz: coarse voxels per axis; w: kMaskRegionOnly | kMaskCoarseRebuilt | kMaskBlockList
  ivec4 nearLo; // xyz: the coarse voxels a moving box comes within the band's reach of, inclusive (empty: lo > hi)
  ivec4 nearHi;
  uint frame;   // the run's frame number: it reads the settling box of the other parity and resets its own
  uint pad0, pad1, pad2;
};

/// A fine-list entry (SdfPipeline::refinedVoxels): x | y << 10 | z << 20; a refine-list entry: a coarse linear index.
/// Either or-ed with kMaskFineFresh when the voxel is new to the mask (no history).
const uint kMaskFineCoords = 0x3FFFFFFFu;
const uint kMaskFineFresh = 0x40000000u;
/// Or-ed into a refine-list entry (and a fine-list entry) of a band voxel out of the view's reach (withinViewReach):
/// its fine voxels take the coarse SDF upsampled instead of a walk.
const uint kMaskOutOfView = 0x80000000u;
/// Or-ed into a refine-list entry of a band voxel listed only because a moving instance came within its reach
/// (refinedForMotionAlone): closest mode leaves each of its fine voxels that no swept box comes near (movedBoxBeyond)
/// as it is. Refine-list entries only: the coarse index fits below it (kMaskCoarseIndex; the coarse
/// state, 8 bytes a voxel, would pass maxStorageBufferRange's 4 GiB first).
const uint kMaskMovedOnly = 0x20000000u;
const uint kMaskCoarseIndex = 0x1FFFFFFFu;

/// Word indices of the counts buffer: a VkDispatchIndirectCommand for the refinement at offset 0, then the
/// counters mask_compact.comp appends with (reset to 0 before it runs).
const uint kMaskCountGroupsX = 0u;
const uint kMaskCountGroupsY = 1u;
const uint kMaskCountGroupsZ = 2u;
const uint kMaskCountFine = 3u;       // fine voxels under the coarse voxels of the refine list: those refined
const uint kMaskCountCoarse = 4u;     // coarse band voxels
const uint kMaskCountMaskedFine = 5u; // fine voxels under the band, refined or kept
const uint kMaskCountRefineList = 6u; // coarse voxels appended to the refine list, those out of view included
const uint kMaskCountOutOfView = 7u;  // of those, the band voxels out of view written again (kMaskOutOfView)
const uint kMaskCountSpreadStride = 8u; // spreadStride of the refinement's groups (MaskDispatchPass writes it)
const uint kMaskCountWords = 9u;

/// Moving instances' boxes MaskCompactPass reads (more are merged into the last one).
#define RTSDF_MAX_MOVED_BOXES 256

/// The box an instance swept from the previous frame to this one: the union of its world bounds in both poses,
/// in the frame the GPU passes measure from (w unused).
struct MovedBox {
  vec4 lo;
  vec4 hi;
};

/// Push constants of mask_compact.comp and mask_dispatch.comp.
/// Flags in MaskParams::coarseDims.w (its bits from 8 on: the growth outOfViewRewritten gives the changed box).
const int kMaskRelistOutOfView = 1; // every band voxel out of view is written again (first frame, pool reset, scroll,
                                    // a new view: bricks may have new slots anywhere)
const int kMaskCoarseRebuilt = 2;   // the coarse SDF was rebuilt this frame: its ChangedBox is this frame's
const int kMaskMotionKeepsSettled = 4; // closest mode: a moving instance does not restart a voxel's settling
                                       // (refinementsAfter)
const int kMaskRegionOnly = 8;         // the run visits the MaskRegion alone, keeps the band's counts and the bricks'
                                       // band counts and changes them where a visited voxel's band or view changed
const int kMaskBlockList = 16;         // with kMaskRegionOnly, the run visits the coarse blocks of a list instead of
                                       // the MaskRegion's box: a work group a block (after a scroll), run by
                                       // MaskCompactPass's variant mask_compact_blocks.comp

struct MaskParams {
  ivec4 coarseDims;    // xyz: coarse voxels per axis; w: kMaskRelistOutOfView | kMaskCoarseRebuilt |
                       // kMaskMotionKeepsSettled | kMaskRegionOnly | kMaskBlockList | growth << 8
  float band;          // d: a coarse voxel is in the band when |c| <= d (the CPU mirror's float comparison)
  uint refineCapacity; // entries the refine list holds (appends beyond it are counted, not written)
  uint pad0;
  uint frame;          // frame number (1, 2, ...)
  vec4 coarseOriginH;  // xyz: corner of coarse voxel (0,0,0) in the GPU's frame, w: coarse voxel size
  float reachPad;      // a fine voxel of the cell is within |c| + reachPad of the surface (see movedWithinReach)
  uint settleFrames;   // refinements in a row after which a voxel is settled; 0: refine every band voxel
  uint refreshPeriod;  // a settled voxel is refined again once every this many frames; 0: never
  uint movedBoxes;     // MovedBox entries this frame
  ivec4 brickDims;     // xyz: bricks per axis; w: the refinement's invocations per coarse voxel (refineParts)
  vec4 viewApex;       // xyz: the camera in the GPU's frame; w: the reach over the cone's cosine (withinViewReach),
                       // < 0: no view limit (every band voxel is refined)
  vec4 viewAxis;       // xyz: the unit view direction; w: the tangent of the view cone's half-angle
};

/// Whether a band voxel whose state is @a state starts afresh (no history to blend with or keep): new to the band (not
/// in it at the last run that visited it: a voxel no run visits keeps its coarse value, so its band), or holding the
/// coarse SDF (out of the view's reach at that run: no refinements).
RTSDF_FN bool startsFresh(MaskParams p, uvec2 state) { return state.x == kNotInBand || state.y == 0u; }

/// How a visited coarse voxel changes the band counts of the bricks over its fine voxels (kMaskBindingBrickNeeded):
/// it counts where it is in the band and in view and has fine voxels (@a now; @a before: as its state said, @a
/// state.y > 0 for a voxel refined in view). A run over every voxel counts from zero (+1 where now); a run over
/// what changed (kMaskRegionOnly) adds the difference.
RTSDF_FN int brickBandDelta(MaskParams p, uvec2 state, bool hasFine, bool now) {
  bool before = hasFine && state.x != kNotInBand && state.y != 0u;
  if ((p.coarseDims.w & kMaskRegionOnly) == 0) return now ? 1 : 0;
  return (now ? 1 : 0) - (before ? 1 : 0);
}

/// Whether coarse voxel @a v lies within the view's reach: its bounding sphere (half the cell's diagonal, widened by
/// the view margin: R) meets the cone around the camera's view direction holding the image (apex at the camera,
/// half-angle a). A point at distance t along the axis and r across it is within R of the cone's side when
/// r cos a - t sin a <= R, i.e. r <= R / cos a + t tan a (the host puts R / cos a in viewApex.w, tan a in viewAxis.w);
/// behind the apex that side's distance is below the true one, so the test errs on the side of refining. Squares
/// only, no square root: the GPU and its CPU copy decide alike.
RTSDF_FN bool withinViewReach(MaskParams p, ivec3 v) {
  if (p.viewApex.w < 0.0) return true;
  RTSDF_PRECISE vec3 centre = vec3(p.coarseOriginH) + (vec3(v) + vec3(0.5)) * p.coarseOriginH.w;
  RTSDF_PRECISE vec3 d = centre - vec3(p.viewApex);
  RTSDF_PRECISE float along = dot(d, vec3(p.viewAxis));
  RTSDF_PRECISE float acrossSq = dot(d, d) - along * along;
  RTSDF_PRECISE float reach = p.viewApex.w + along * p.viewAxis.w;
  return reach >= 0.0 && acrossSq <= reach * reach;
}

/// Whether band voxel @a v, out of the view's reach with state @a state (before this frame), has its fine voxels
/// written again this frame (listed with kMaskOutOfView): always with kMaskRelistOutOfView; when it was not kept
/// coarse in the last run (it left the view or entered the band); and where the coarse SDF changed, @a changedLo ..
/// @a changedHi (a ChangedBox, empty when lo.x > hi.x), grown by the growth in coarseDims.w's bits from 8: a cell
/// and its neighbours (the upsampling's stencil), and a brick's width besides, since a brick that a voxel coming into
/// the band takes anew holds no values yet for the cells beside it. Elsewhere its voxels keep what they hold.
RTSDF_FN bool outOfViewRewritten(MaskParams p, uvec2 state, ivec3 v, uvec4 changedLo, uvec4 changedHi) {
  if ((p.coarseDims.w & kMaskRelistOutOfView) != 0) return true;
  if (state.x == kNotInBand || state.y != 0u) return true;
  if ((p.coarseDims.w & kMaskCoarseRebuilt) == 0 || changedLo.x > changedHi.x) return false;
  int grow = p.coarseDims.w >> 8;
  ivec3 lo = ivec3(changedLo.x, changedLo.y, changedLo.z) - ivec3(grow);
  ivec3 hi = ivec3(changedHi.x, changedHi.y, changedHi.z) + ivec3(grow);
  return v.x >= lo.x && v.y >= lo.y && v.z >= lo.z && v.x <= hi.x && v.y <= hi.y && v.z <= hi.z;
}

/// Incremental refinement, decided per coarse band voxel for all the fine voxels under it: whether they are
/// refined this frame (else they keep their values). They are when every band voxel is (settleFrames == 0), when
/// the voxel is new to the band (@a fresh), when a moving instance came within reach (@a nearMoved), while it has
/// had fewer than settleFrames refinements in a row, and, settled, once every refreshPeriod frames (staggered by
/// the coarse index @a voxel).
RTSDF_FN bool refinesThisFrame(MaskParams p, bool fresh, bool nearMoved, uint refinements, uint voxel) {
  if (p.settleFrames == 0u || fresh || nearMoved || refinements < p.settleFrames) return true;
  return p.refreshPeriod != 0u && (voxel + p.frame) % p.refreshPeriod == 0u;
}

/// The voxel's refinements in a row after this frame: restarted by entering the band or, in rays mode, a moving
/// instance (its blend starts again), counted up while refined (saturating), unchanged while kept. Closest mode
/// (kMaskMotionKeepsSettled) does not restart on motion: a walk gives the exact distance, and the sign's votes need no
/// new start, since a ray's first hit votes right whatever moved (a back face from inside a closed surface, a front
/// face from outside). So a voxel near a moving instance settles as any other, and is then listed for the motion
/// alone (kMaskMovedOnly), where the refinement keeps each fine voxel that no swept box came near (movedBoxBeyond);
/// a restart would walk it whole again and again while the instance stays near, and for settleFrames - 1 frames after.
RTSDF_FN uint refinementsAfter(MaskParams p, bool refined, bool fresh, bool nearMoved, uint refinements) {
  if (!refined) return refinements;
  if (fresh || (nearMoved && (p.coarseDims.w & kMaskMotionKeepsSettled) == 0)) return 1u;
  return refinements == 0xFFFFFFFFu ? refinements : refinements + 1u;
}

/// Whether band voxel @a voxel, with @a refinements before this frame, is refined only because a moving instance came
/// within reach (@a nearMoved): not new to the band (@a fresh), settled and not due for a refresh (kMaskMovedOnly).
RTSDF_FN bool refinedForMotionAlone(MaskParams p, bool fresh, bool nearMoved, uint refinements, uint voxel) {
  return !fresh && nearMoved && !refinesThisFrame(p, false, false, refinements, voxel);
}

/// The distance a moving box must keep from a fine voxel whose value before this frame was @a lastValue (exact in
/// closest mode) for the voxel to keep it (movedBoxBeyond): |f| plus a relative 1e-5 and a hundredth of the fine voxel
/// @a fineVoxel, for rounding.
RTSDF_FN float movedKeepReach(float lastValue, float fineVoxel) {
  return abs(lastValue) * 1.00001f + 0.01f * fineVoxel;
}

/// Whether moving box @a b lies farther than @a reach (movedKeepReach) from a fine voxel's centre @a q. Where every
/// box does, the voxel's value cannot change (the refinement keeps it, kMaskMovedOnly): its nearest surface was not
/// the instance in its old pose, which lies at least as far as the box, and the new pose lies as far, so the same
/// static surface stays nearest; the point lies in neither pose, so no sign rule changes (the nearest triangle's side
/// and its mesh's winding number are the static surface's; a closed piece holding the point and another's surface
/// nearer than its own overlaps that other without the instance).
RTSDF_FN bool movedBoxBeyond(vec3 q, float reach, MovedBox b) {
  RTSDF_PRECISE vec3 gap = max(max(vec3(b.lo) - q, q - vec3(b.hi)), vec3(0.0));
  return dot(gap, gap) > reach * reach;
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

/// The indirect dispatch of @a invocations refinement invocations in groups of RTSDF_REFINE_GROUP: at most 65535
/// groups along x, the rest along y (the refinement flattens them); no groups at all for an empty mask.
RTSDF_FN uvec3 refineDispatch(uint invocations) {
  uint groups = invocations / uint(RTSDF_REFINE_GROUP) + (invocations % uint(RTSDF_REFINE_GROUP) != 0u ? 1u : 0u);
  if (groups == 0u) return uvec3(0u, 0u, 1u);
  uint gx = min(groups, 65535u);
  return uvec3(gx, (groups + gx - 1u) / gx, 1u);
}

/// The greatest common divisor of @a a and @a b.
RTSDF_FN uint greatestCommonDivisor(uint a, uint b) {
  while (b != 0u) {
    uint r = a % b;
    a = b;
    b = r;
  }
  return a;
}

/// The stride that spreads the refinement's @a groups over its list (kRefineSpreadGroups): group g takes the list's
/// group (g * stride) mod groups. The first odd stride from groups / golden ratio on that is coprime to groups, so a
/// permutation in which any run of consecutive groups takes positions spread evenly over the list. Lavapipe gives each
/// of its threads a run of a dispatch's groups, and the list keeps the voxels near a moving instance together, so in
/// list order one thread walked most of them while the other waited (ClosestRefinePass 1.6x slower, measured). Past
/// 65535 groups (the product would overflow) and below 3: 1, the list's order. MaskDispatchPass computes it once a
/// frame (kMaskCountSpreadStride).
RTSDF_FN uint spreadStride(uint groups) {
  if (groups < 3u || groups > 65535u) return 1u;
  uint s = (groups * 618u / 1000u) | 1u;
  while (greatestCommonDivisor(s, groups) != 1u) s += 2u; // ends by groups - 1 or groups - 2, both coprime
  return s;
}

/// The list's group that group @a g of @a groups takes with the spread (spreadStride).
RTSDF_FN uint spreadGroup(uint g, uint groups) { return g * spreadStride(groups) % groups; }

RTSDF_SHARED_END

#endif
