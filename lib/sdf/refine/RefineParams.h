// Shared by C++ and GLSL: the fine-SDF refinement's parameters and bindings (refine_main.glsl,
// refine_upsample_main.glsl) and its random numbers (PCG hash, identical integer arithmetic on both sides). The
// ray mask and the brick pool it refines under are sdf/mask/MaskParams.h's.
#ifndef RTSDF_SDF_REFINE_REFINEPARAMS_H
#define RTSDF_SDF_REFINE_REFINEPARAMS_H
#include "bvh/GpuBvhLayout.h"
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
/// Bindings of upsample_region.comp (UpsampleRegionPass).
const uint kUpsampleRegionBindingChanged = 0u; // the coarse SDF's ChangedBox (sdf/coarse/CoarseParams.h; read)
const uint kUpsampleRegionBindingRegion = 1u;  // UpsampleRegion (written)
const uint kUpsampleRegionBindingCount = 2u;

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

/// The fine voxels UpsamplePass writes, [begin, end) per axis, and the work groups that cover them (groups.xyz: a
/// VkDispatchIndirectCommand at offset 0, refine_upsample.comp's groups).
struct UpsampleRegion {
  uvec4 groups;
  ivec4 begin;
  ivec4 end;
};

/// The fine voxels whose upsampled value may differ once the coarse voxels in @a lo..@a hi (inclusive; empty where
/// lo.x > hi.x) changed, with the work groups of refine_upsample.comp (runs of @a run voxels along z). A fine voxel
/// reads its cell's eight corners and its own coarse voxel (the band test): both lie within one coarse voxel of it,
/// so the region is the fine voxels of the box grown by one coarse voxel, and one fine voxel more each side for
/// rounding; where the grown box reaches a face of the coarse grid, the region reaches the fine grid's face (the
/// cells clamp there). The slots of the bricks change only where the band does, so inside the box as well.
RTSDF_FN UpsampleRegion upsampleRegionOf(uvec4 lo, uvec4 hi, RefineParams p, int run) {
  UpsampleRegion r;
  r.groups = uvec4(0u, 1u, 1u, 0u);
  r.begin = ivec4(0);
  r.end = ivec4(0);
  if (lo.x > hi.x) return r;
  ivec3 cd = ivec3(p.coarseDims), fd = ivec3(p.fineDims);
  ivec3 clo = max(ivec3(uvec3(lo)) - ivec3(1), ivec3(0));
  ivec3 chi = min(ivec3(uvec3(hi)) + ivec3(1), cd - ivec3(1));
  // Corners of the grown box relative to the fine grid's corner, in fine voxels.
  vec3 toFine = vec3(p.coarseOriginInvH) - vec3(p.fineOriginH);
  vec3 a = (toFine + vec3(clo) / p.coarseOriginInvH.w) / p.fineOriginH.w;
  vec3 b = (toFine + vec3(chi + ivec3(1)) / p.coarseOriginInvH.w) / p.fineOriginH.w;
  ivec3 begin = ivec3(floor(a)) - ivec3(1), end = -ivec3(floor(-b)) + ivec3(1);
  for (int i = 0; i < 3; ++i) {
    if (clo[i] == 0) begin[i] = 0;
    if (chi[i] == cd[i] - 1) end[i] = fd[i];
  }
  begin = clamp(begin, ivec3(0), fd);
  end = clamp(end, begin, fd);
  ivec3 n = end - begin;
  r.begin = ivec4(begin, 0);
  r.end = ivec4(end, 0);
  r.groups = uvec4(uint((n.x + RTSDF_UPSAMPLE_GROUP_X - 1) / RTSDF_UPSAMPLE_GROUP_X),
                   uint((n.y + RTSDF_UPSAMPLE_GROUP_Y - 1) / RTSDF_UPSAMPLE_GROUP_Y), uint((n.z + run - 1) / run), 0u);
  return r;
}

/// The two uniform numbers in [0, 1) of ray @a ray of voxel @a voxel in frame @a frame.
RTSDF_FN uint rayHash(uint voxel, uint frame, uint ray, uint seed) {
  return pcgHash(voxel ^ pcgHash(frame * 0x9E3779B9u + pcgHash(ray + seed * 0x85EBCA6Bu)));
}

RTSDF_SHARED_END

#endif
