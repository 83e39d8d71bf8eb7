// Shared by C++ and GLSL: the fine-SDF refinement's parameters and bindings (refine_main.glsl,
// refine_upsample_main.glsl) and its random numbers (PCG hash, identical integer arithmetic on both sides). The
// ray mask and the brick pool it refines under are sdf/mask/MaskParams.h's.
#ifndef RTSDF_SDF_REFINE_REFINEPARAMS_H
#define RTSDF_SDF_REFINE_REFINEPARAMS_H
#include "bvh/GpuBvhLayout.h"
#include "sdf/coarse/CoarseParams.h"
#include "sdf/mask/MaskParams.h"

RTSDF_SHARED_BEGIN

/// Refinement modes: the shaders refine_rays.comp and refine_closest*.comp (ClosestRefinePass::Variant) are
/// refine_main.glsl compiled with RTSDF_REFINE_MODE set to one of these (lib/Shaders.cmake).
#define RTSDF_REFINE_RAYS 0    // the paper: x random rays per voxel per frame, nearest hit, decayed history
#define RTSDF_REFINE_CLOSEST 1 // exact closest-point distance through the same BVH, deterministic

/// Work-group shape of refine_upsample.comp (x fastest in memory; one invocation per run along z).
#define RTSDF_UPSAMPLE_GROUP_X 32
#define RTSDF_UPSAMPLE_GROUP_Y 2
/// Fine voxels along z per invocation of refine_upsample.comp.
#define RTSDF_UPSAMPLE_RUN_LENGTH 16
/// Closest mode's cell search: the most triangles one box's walk keeps for its voxels to test (more: the nearest to
/// the box's centre are kept, and a voxel whose answer may lie as far as a dropped one walks the BVH on its own).
#define RTSDF_CELL_CANDIDATES 24
/// The most fine voxels along an axis of a cell-search box (refinePartsFor): 2, so that every voxel of a box is one
/// of its 8 corners (the corner bounds of the cell search, refine_main.glsl).
#define RTSDF_CELL_BOX 2
/// Loop steps each invocation of the closest shaders for CPU devices (refine_closest*_cpu.comp) may spend on BVH and
/// winding walks (RTSDF_LOOP_BUDGET, bvh_traverse.glsl): lavapipe ends every loop once the 8 lanes of a subgroup have
/// run 65535 iterations in all, so 8 x 7000 leaves room for the fixed loops. A voxel whose walk the budget ended
/// keeps the nearest found (an upper bound of the distance) and is counted (kRefineStatCutVoxels).
#define RTSDF_CPU_LOOP_BUDGET 7000

/// Closest mode with sign rays: the rays' votes sign a voxel only where the nearest triangle's side is in doubt, the
/// voxel within this |cos| of the plane of the triangle that gave the side (a knife edge's rim, where every face that
/// ties lies edge-on), or no triangle was found. Elsewhere the side is the exact field's rule on closed pieces (turned
/// outward at load), and the votes of a few rays are not: a ray that slips between two triangles' shared edge meets
/// the far side's back face, and one such vote put voxels outside the default scene's walls inside (12.4 voxels off
/// at size S with x = 1).
const float kSignVoteFacing = 0.1f;

/// Flags of RefineParams::coarseDims.w in the refinement shaders.
const int kRefineWriteDense = 1; // f_t is also written to the dense fine SDF (FineStorage::Dense)
const int kRefineCellSearch = 2; // closest mode: one BVH walk per box collects candidates its voxels test
const int kRefineSpreadGroups = 4; // CPU devices: the groups take the list in spreadStride's order (MaskParams.h)
/// Bits of RefineParams::coarseDims.w from this one on: the moving instances' boxes this frame
/// (kRefineBindingMovedBoxes).
const int kRefineMovedBoxesShift = 8;

/// Bindings of refine_upsample.comp.
const uint kUpsampleBindingCoarse = 0u;       // coarse SDF c_t (read)
const uint kUpsampleBindingFine = 1u;         // the dense fine SDF: c_t upsampled outside the ray mask (the
                                              // refinement wrote the masked voxels whose bricks have a slot)
const uint kUpsampleBindingFineToCoarse = 2u; // int per fine index per axis (x entries, then y, then z): the coarse
                                              // voxel whose slab holds it (maskCoarseOfFine), -1: none
const uint kUpsampleBindingBrickSlots = 3u;   // uint per brick: its slot in the pool, kNoBrick: none
const uint kUpsampleBindingRegion = 4u;       // UpsampleRegion: the fine voxels written (read)
const uint kUpsampleBindingCount = 5u;
/// Bindings of refine_upsample_blocks.comp: kUpsampleBinding{Coarse, Fine, FineToCoarse, BrickSlots}, then these.
const uint kUpsampleBindingBlockList = 4u;      // UpsampleBlockList: the coarse blocks whose fine voxels are written
const uint kUpsampleBindingFineBegins = 5u;     // upsampleBlockFineBegins: each block's fine voxels
const uint kUpsampleBlocksKernelBindingCount = 6u;
/// Bindings of upsample_blocks.comp (UpsampleBlocksPass).
const uint kUpsampleBlocksBindingMarks = 0u;      // uint per coarse block: CoarseDistancePass's changedBlockReach bits
const uint kUpsampleBlocksBindingBoxes = 1u;      // UpsampleBoxes: coarse voxels to upsample near, whatever changed
const uint kUpsampleBlocksBindingFineBegins = 2u; // upsampleBlockFineBegins (read: the listed fine voxels' count)
const uint kUpsampleBlocksBindingList = 3u;       // UpsampleBlockList (written; its header reset by the host)
const uint kUpsampleBlocksBindingCount = 4u;

/// Work-group side of refine_upsample_blocks.comp: RTSDF_UPSAMPLE_BLOCK_GROUP^2 invocations, each a column along z of
/// a listed block's fine voxels.
#define RTSDF_UPSAMPLE_BLOCK_GROUP 8
/// Work-group size of upsample_blocks.comp's listing (one invocation per coarse block).
#define RTSDF_UPSAMPLE_BLOCKS_GROUP 64
/// The most coarse boxes one upsampling over blocks takes besides the changed voxels (a scroll's: a slab that entered
/// and a face left behind per axis, scrollUpsampleBoxes).
#define RTSDF_UPSAMPLE_MAX_BOXES 6
/// The coarse boxes (inclusive; count.x of them) near which every fine voxel is upsampled again, whatever changed.
struct UpsampleBoxes {
  ivec4 count;
  ivec4 lo[RTSDF_UPSAMPLE_MAX_BOXES];
  ivec4 hi[RTSDF_UPSAMPLE_MAX_BOXES];
};
/// Push constants of upsample_blocks.comp: coarseDims.xyz the coarse grid, w the phase.
struct UpsampleBlocksParams {
  ivec4 coarseDims;
};
#define RTSDF_UPSAMPLE_BLOCKS_LIST 0     // one invocation per coarse block: those to upsample listed
#define RTSDF_UPSAMPLE_BLOCKS_DISPATCH 1 // one invocation: the indirect dispatch of refine_upsample_blocks.comp
/// The list of an upsampling over blocks, at the head of its buffer (then the blocks, coarseBlockIndex, in no
/// particular order): groups.xyz the indirect dispatch of refine_upsample_blocks.comp (a group a block, in rows of
/// kCoarseRegionGroupsX), groups.w the listed blocks; totals.x their fine voxels. The host resets it to
/// kUpsampleBlockListEmpty before the listing.
struct UpsampleBlockListHeader {
  uvec4 groups;
  uvec4 totals;
};
const uint kUpsampleBlockListHeaderWords = 8u;

/// Words of upsampleBlockFineBegins for a coarse grid of @a dims: per axis the blocks' first fine voxels and the end.
RTSDF_FN uint upsampleBlockFineBeginWords(ivec3 dims) {
  ivec3 bd = coarseBlockDims(dims);
  return uint(bd.x + bd.y + bd.z + 3);
}

/// The words of upsampleBlockFineBegins where axis @a axis's entries start (x's, then y's, then z's; per axis the
/// first fine voxel of each block, then the end), for a grid of @a bd blocks.
RTSDF_FN int upsampleBlockFineAt(ivec3 bd, int axis) { return axis == 0 ? 0 : axis == 1 ? bd.x + 1 : bd.x + bd.y + 2; }

/// Whether coarse block @a b meets box @a boxLo..@a boxHi grown by one voxel (the upsampling's stencil).
RTSDF_FN bool upsampleBlockMeetsBox(ivec3 b, ivec3 dims, ivec3 boxLo, ivec3 boxHi) {
  ivec3 lo = b * RTSDF_COARSE_BLOCK, hi = min(lo + ivec3(RTSDF_COARSE_BLOCK - 1), dims - ivec3(1));
  return all(lessThanEqual(lo, boxHi + ivec3(1))) && all(greaterThanEqual(hi, boxLo - ivec3(1))) &&
         all(lessThanEqual(boxLo, boxHi));
}

/// Bindings of refine_rays.comp and refine_closest*.comp: the scene BVH (GpuBvhLayout.h's kBvhBinding*), then these,
/// then the brick pool's value pages (kRefineBindingValuePages + page) and vote pages (kRefineBindingVotePages + page),
/// then the closed pieces' union (piece_union.glsl), then the open meshes' winding number (open_winding.glsl).
const uint kRefineBindingRefineList = kBvhBindingCount + 0u; // the coarse voxels to refine (MaskCompactPass's list)
const uint kRefineBindingMaskCounts = kBvhBindingCount + 1u; // MaskCounts words: the list's size
const uint kRefineBindingCoarse = kBvhBindingCount + 2u;     // coarse SDF c_t (upsampled for the bound)
const uint kRefineBindingFineRanges = kBvhBindingCount + 3u; // maskFineRanges(): the fine voxels of a coarse voxel
const uint kRefineBindingBrickSlots = kBvhBindingCount + 4u; // uint per brick: its slot in the pool
const uint kRefineBindingDense = kBvhBindingCount + 5u;      // the dense fine SDF: f_t also written here when
                                                             // coarseDims.w != 0 (FineStorage::Dense)
const uint kRefineBindingValuePages = kBvhBindingCount + 6u; // in: f_{t-1} signed (not fresh); out: f_t signed
const uint kRefineBindingVotePages = kRefineBindingValuePages + RTSDF_BRICK_PAGES; // decayed (front, back) hits
const uint kRefineBindingPieceOf = kRefineBindingVotePages + RTSDF_BRICK_PAGES; // GpuSceneBvh::pieceOf()
const uint kRefineBindingUnionPieces = kRefineBindingPieceOf + 1u; // GpuSceneBvh::unionPieces(): this frame's overlap
const uint kRefineBindingOpenFlags = kRefineBindingUnionPieces + 1u; // GpuSceneBvh::openFlags(): open meshes' rims
const uint kRefineBindingWindingNodes = kRefineBindingOpenFlags + 1u; // GpuSceneBvh::windingNodes(): their dipoles
const uint kRefineBindingStats = kRefineBindingWindingNodes + 1u; // kRefineStat* words (zeroed every frame)
const uint kRefineBindingWindingDoubts = kRefineBindingStats + 1u; // closest mode: the voxels WindingExactPass signs
const uint kRefineBindingMovedBoxes = kRefineBindingWindingDoubts + 1u; // MaskCompactPass's MovedBox entries
const uint kRefineBindingCount = kRefineBindingMovedBoxes + 1u;

/// Words of the refinement's statistics buffer (kRefineBindingStats).
const uint kRefineStatCutVoxels = 0u; // fine voxels whose walks the loop budget ended (CPU devices' shaders only)
const uint kRefineStatNearHalf = 1u;  // fine voxels whose walked winding number lay within kWindingExactBand of 1/2
const uint kRefineStatNearHalfKept = 2u; // of those, left with the walked number's side (list full, mesh too large)
const uint kRefineStatMovedKept = 3u; // fine voxels of kMaskMovedOnly entries no swept box came near: not walked
const uint kRefineStatWords = 4u;

/// WindingExactPass (winding_exact.comp): the winding number of the voxels the refinement's walks left near 1/2
/// (kWindingExactBand), summed over every triangle of the mesh by one work group per voxel, each invocation every
/// RTSDF_WINDING_EXACT_GROUP-th triangle. The list (kRefineBindingWindingDoubts): a VkDispatchIndirectCommand
/// (x: entries, y = z = 1) in a uvec4, then kWindingExactCapacity entries (a dispatch's guaranteed group count)
/// of uvec4(dense index, brick slot, offset in the brick, instance slot). A mesh of more than
/// kWindingExactMaxTriangles is not summed: on a CPU device each invocation's loop must stay in its budget.
#define RTSDF_WINDING_EXACT_GROUP 128
const uint kWindingExactCapacity = 65535u;
const uint kWindingExactMaxTriangles = RTSDF_WINDING_EXACT_GROUP * RTSDF_CPU_LOOP_BUDGET;
const uint kWindingExactBindingDoubts = kBvhBindingCount + 0u; // the list above
const uint kWindingExactBindingDense = kBvhBindingCount + 1u;  // the dense fine SDF (kRefineWriteDense)
const uint kWindingExactBindingTriangles = kBvhBindingCount + 2u; // per instance slot: uvec2(first leaf-ordered
                                                                  // triangle of its mesh, count)
const uint kWindingExactBindingStats = kBvhBindingCount + 3u;  // the refinement's kRefineStat* words
const uint kWindingExactBindingValuePages = kBvhBindingCount + 4u; // the brick pool's value pages
const uint kWindingExactBindingCount = kWindingExactBindingValuePages + RTSDF_BRICK_PAGES;

/// Push constants of refine_upsample.comp and the refinement shaders.
struct RefineParams {
  vec4 fineOriginH;      // xyz: world corner of fine voxel (0,0,0), w: fine voxel size
  ivec4 fineDims;        // xyz: fine voxels per axis, w: the brick pool's capacity (bricks)
  vec4 coarseOriginInvH; // xyz: world corner of coarse voxel (0,0,0), w: 1 / coarse voxel size
  ivec4 coarseDims;      // xyz: coarse voxels per axis; w: refinement: kRefine* flags | boxes << kRefineMovedBoxesShift
  float alpha;           // history decay
  uint rays;             // x, rays per masked voxel per frame
  uint frame;            // frame number (1, 2, ...)
  uint seed;             // per-run random seed
  float beta;            // the coarse shell (closest mode widens its search by it)
  float band;            // upsample: > 0 reads the fine voxels under band coarse voxels (|c| <= d) from the bricks
  uint pageBricks;       // bricks per page of the pool
  uint refineParts;      // refinement invocations per coarse voxel of the list: boxes (x fastest) of partBox.xyz
  ivec4 brickDims;       // xyz: bricks per axis; w: boxes along x per coarse voxel
  ivec4 partBox;         // xyz: the most fine voxels per axis of one invocation's box; w: boxes along y
};

/// The fine voxels UpsamplePass writes over the whole grid, [begin, end) per axis (end clamped to the grid), with
/// room for the work groups that cover them (groups).
struct UpsampleRegion {
  uvec4 groups;
  ivec4 begin;
  ivec4 end;
};

/// The fine voxels @a lo..@a hi of refinement invocation @a part of a listed coarse voxel whose fine voxels are
/// @a rx, @a ry, @a rz along the axes (maskFineRanges): boxes of @a p.partBox.xyz voxels, p.brickDims.w along x and
/// p.partBox.w along y a layer. False where the part holds none. The refinement (refine_main.glsl) and the copies
/// that follow what it wrote (volume_update.comp) cut the voxels alike.
RTSDF_FN bool refinePartBox(RefineParams p, ivec2 rx, ivec2 ry, ivec2 rz, uint part, RTSDF_OUT(ivec3) lo,
                            RTSDF_OUT(ivec3) hi) {
  uint partsX = uint(p.brickDims.w), partsY = uint(p.partBox.w);
  ivec3 box = ivec3(p.partBox);
  lo = ivec3(rx.x, ry.x, rz.x) + box * ivec3(int(part % partsX), int(part / partsX % partsY), int(part / (partsX * partsY)));
  hi = min(lo + box - ivec3(1), ivec3(rx.y, ry.y, rz.y));
  return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
}

/// The two uniform numbers in [0, 1) of ray @a ray of voxel @a voxel in frame @a frame.
RTSDF_FN uint rayHash(uint voxel, uint frame, uint ray, uint seed) {
  return pcgHash(voxel ^ pcgHash(frame * 0x9E3779B9u + pcgHash(ray + seed * 0x85EBCA6Bu)));
}

RTSDF_SHARED_END

#endif
