#pragma once
/// @file FramePlan.h
/// @brief Which passes a frame of an SdfPipeline runs: only those whose inputs changed since they last ran
///        (planFrame); the others' buffers keep what they wrote then, which is what they would write again.
#include "sdf/PipelineSettings.h"

#include <string>
#include <vector>

namespace rtsdf {

/// @brief What changed since the previous frame, as the host knows it before recording a frame.
struct FrameChanges {
  bool first = true;        ///< no frame has run: every buffer is to be written
  bool moved = false;       ///< an instance's transform differs from the previous frame's (movedInstanceBoxes)
  bool poolReset = false;   ///< the brick pool was (re)allocated for this frame: every coarse voxel is new to the band
  bool scrolled = false;    ///< the grids moved (SdfPipeline::scroll): the cells that entered are new to every buffer
  /// The scroll moved the coarse SDF with the grids (CoarseSdfBuilder::scrollMovedDistances): the next build's
  /// ChangedBox holds the coarse voxels whose value differs from their moved one.
  bool scrollMovedCoarse = false;
  /// The mask carried its counts and bricks over the scroll (GpuRayMask::carriesOverScroll), so that its next run may
  /// visit only the coarse blocks of what changed.
  bool scrollCarriesMask = false;
  bool lastListed = true;   ///< the mask's last run listed voxels to refine (some may still be settling)
  bool viewChanged = false; ///< the view's reach changed (SdfPipeline::setViewReach): voxels enter or leave it
  bool viewLimited = false; ///< the band is refined only within a view's reach
};

/// @brief The passes one frame runs. Coarse: VoxelizePass, the nearest-seed transform and CoarseDistancePass; mask:
///        MaskCompactPass, BrickAllocPass and MaskDispatchPass, with the refinement they dispatch; upsample:
///        UpsamplePass (dense fine storage only).
struct FramePlan {
  bool coarse = true, mask = true, refine = true, upsample = true;
  /// The upsampling rewrites only the fine voxels near the coarse voxels whose value the rebuild changed
  /// (UpsampleRegionPass), and after a scroll those near the voxels that entered and the faces the grids moved away
  /// from (scrollUpsampleBoxes): an instance moved, or the grids scrolled with their coarse SDF
  /// (scrollMovedCoarse), and the pool is as it was.
  bool upsampleChanged = false;
  /// The coarse SDF is built over what the moving instances' seeds can reach (CoarseSdfBuilder::record with their
  /// box): only instances moved, and coarseBuiltOverChanges.
  bool coarseOverChange = false;
  /// The moving instances' seeds are voxelized in their box alone: coarseOverChange, or where the grids also scrolled
  /// (CoarseSdfBuilder keeps the seeds that stayed in the grid and voxelizes those that entered and the box).
  bool coarseMovedSeeds = false;
  /// The mask visits only the coarse voxels whose decisions can change (MaskRegionPass, kMaskRegionOnly): the
  /// pool and the view are as they were, no view limits the band, settled voxels stay settled (settleFrames > 0, no
  /// refresh period), and the grids are as they were or scrolled with their coarse SDF and the mask's counts
  /// (scrollMovedCoarse, scrollCarriesMask).
  bool maskOverChange = false;
  /// maskOverChange after a scroll: the mask visits the coarse blocks the changed voxels, the entered ones, the
  /// settling box and the moving boxes reach (kMaskBlockList), not one box (it would span the level).
  bool maskOverBlocks = false;
};

/// @brief Whether a pipeline under @a s keeps the exact transform from frame to frame, so that a frame where only
///        instances moved builds the coarse SDF over what they reach: the exact transform (Edt), and frames not
///        rebuilt whole by setting (fullRebuild, fullRecompute).
bool coarseBuiltOverChanges(const PipelineSettings& s);

/// @brief The passes a frame with @a changes runs under the settings in effect @a s. Every pass runs with
///        fullRebuild or fullRecompute and on the first frame. Otherwise the coarse SDF is rebuilt only when an
///        instance moved (its inputs are the instances' triangles and transforms); the mask runs when the coarse SDF
///        changed (an instance moved or the grids scrolled), the pool was reset, the view's reach changed, or a band
///        voxel may be due a refinement: while the last run listed any (the
///        voxels still settling), and every frame where settled voxels are refreshed (refreshPeriod > 0: staggered
///        over the frames) or never settle (settleFrames 0). A run that lists nothing leaves the band, the bricks
///        and the fine SDF as they are, so skipping it changes nothing. The upsampling writes the coarse SDF
///        outside the slotted band: it runs when the coarse SDF or the slots changed, over the whole grid unless only
///        an instance moved (then where the coarse SDF changed: the slots change only where the band does) or the
///        grids scrolled with their coarse SDF (then also where they entered and at the faces they left). The coarse
///        SDF is built over what changed where only an instance moved (coarseOverChange); the mask visits what
///        changed (maskOverChange), after a scroll by blocks (maskOverBlocks).
FramePlan planFrame(const FrameChanges& changes, const PipelineSettings& s);

/// @brief The profiler names of the passes @a plan leaves out under @a s (in recording order), for FrameStats.
std::vector<std::string> skippedPasses(const FramePlan& plan, const PipelineSettings& s);

} // namespace rtsdf
