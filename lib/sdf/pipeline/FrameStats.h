#pragma once
/// @file FrameStats.h
/// @brief What one frame of an SdfPipeline did and cost (FrameStats).
#include "util/PassTimes.h"

#include <cstdint>
#include <algorithm>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief What one frame did and cost.
struct FrameStats {
  double time = 0.0;
  std::uint64_t maskCoarseVoxels = 0, maskFineVoxels = 0;
  std::uint64_t refinedFineVoxels = 0; ///< masked fine voxels refined this frame (the others kept their value)
  /// Of those, the voxels listed only for a moving instance that none came near (closest mode:
  /// gpu::shared::movedBoxBeyond): they kept their value, unwalked.
  std::uint64_t movedKeptVoxels = 0;
  /// Of those, the voxels whose BVH walks a CPU device's loop budget ended (RTSDF_CPU_LOOP_BUDGET): each keeps the
  /// nearest surface found, an upper bound of its distance, and a sign that may be wrong.
  std::uint64_t cutVoxels = 0;
  /// Closest mode: refined voxels whose walked winding number lay within kWindingExactBand of 1/2, signed by the
  /// exact sum over their mesh (WindingExactPass) but for nearHalfKept of them (the list was full or the mesh too
  /// large to sum: they keep the walked number's side, which may be wrong).
  std::uint64_t nearHalfVoxels = 0, nearHalfKept = 0;
  std::uint64_t activeBricks = 0;      ///< bricks holding fine voxels under the band (each has a pool slot...)
  std::uint64_t overflowBricks = 0;    ///< ...but these: the pool was full; the next frame grows it and starts over
  std::uint64_t poolBricks = 0;        ///< the pool's capacity this frame
  std::uint64_t deviceBytes = 0;       ///< the pipeline's device buffers this frame (estimate and pool)
  /// Dense fine voxels the upsampling visited this frame: the whole grid, or after an instance moved or a scroll
  /// those of the coarse blocks that the changed coarse voxels reach (UpsampleBlocksPass), after a scroll also near
  /// the voxels that entered and the faces left behind; 0 where it did not run.
  std::uint64_t upsampledFineVoxels = 0;
  /// Coarse voxels whose distance the coarse SDF's build wrote this frame: the whole grid, or where only instances
  /// moved the region their seeds can reach (CoarseRegionPass), or after a scroll by whole blocks the region the
  /// seeds that entered and left reach, with theirs; 0 where it did not run.
  std::uint64_t coarseRebuiltVoxels = 0;
  /// Coarse voxels whose seeds VoxelizePass wrote this frame: the whole grid, or where only instances moved the box
  /// of their seeds (movedSeedBox: the seeds elsewhere are the last build's), or after a scroll the voxels that
  /// entered and that box (CoarseSdfBuilder::recordScroll); 0 where it did not run.
  std::uint64_t coarseVoxelizedVoxels = 0;
  /// Coarse voxels the mask's compaction visited this frame: the whole grid, or where its inputs changed only near
  /// moving instances those whose decisions can change (MaskRegionPass's box; after a cascade level's scroll the
  /// blocks of what changed: FramePlan::maskOverBlocks); 0 where it did not run.
  std::uint64_t maskVisitedVoxels = 0;
  std::uint64_t movedInstances = 0;    ///< instances whose transform changed since the previous frame near the grid
  /// CPU time of the frame outside its wait for the GPU: the BVH's top level and the instance transforms,
  /// recording, submitting, and reading the counts after the GPU finished. It grows with the instances, not with
  /// their triangles or the voxels (the GPU places the triangles and compacts the ray mask).
  double hostMs = 0.0;
  double wallMs = 0.0; ///< submitFrame() to the return of finishFrame(): host work, submission and the GPU's work
  PassTimes passMs;      ///< GPU time per pass
  /// The passes this frame did not run, their inputs unchanged since they last ran (planFrame): their buffers hold
  /// what they wrote then. Empty with PipelineSettings::fullRebuild.
  std::vector<std::string> skippedPasses;
  /// Whether the frame wrote the fields shading samples (the coarse SDF, the fine SDF or the bricks); false: they
  /// hold the previous frame's values, so a copy of them (the shading's 3D texture) is still current.
  bool fieldChanged = true;
  bool skipped(const std::string& pass) const {
    return std::find(skippedPasses.begin(), skippedPasses.end(), pass) != skippedPasses.end();
  }
  double passTotal(const std::string& pass) const { return rtsdf::passTotal(passMs, pass); }
  /// @brief The refinement's time, whichever mode ran (RayRefinePass, or ClosestRefinePass and WindingExactPass).
  double refineMs() const;
};

} // namespace rtsdf
