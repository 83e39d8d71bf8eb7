#pragma once
/// @file GpuRayMask.h
/// @brief The ray mask of one pipeline on the GPU: MaskCompactPass and MaskDispatchPass with the buffers they write,
///        their parameters, the counts read back after a frame, and the compacted mask's read-backs.
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "sdf/refine/RefineParams.h"
#include "grid/GridSpec.h"
#include "sdf/PipelineSettings.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/pipeline/BrickPool.h"
#include "sdf/pipeline/RayMask.h"
#include "sdf/pipeline/ViewReach.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

class GridShiftPass;

/// @brief @a region's two settling boxes after its coarse grid of @a dims scrolled by @a shift voxels (voxel v takes
///        v + shift's): moved with their voxels and clipped to the grid, empty where all of a box left.
gpu::shared::MaskRegion settlingMovedWith(gpu::shared::MaskRegion region, const glm::ivec3& dims,
                                          const glm::ivec3& shift);

/// @brief The ray mask compacted on the GPU, for one pair of grids.
///
/// Owns the three passes and their buffers: the grids' tables (maskFineRanges: "ray mask fine ranges";
/// maskCoarseOfFine: "ray mask fine-to-coarse table"), uploaded once; per coarse voxel the refinement's history
/// ("coarse refinement state": the run that last visited it in the band or kNotInBand, refinements in a row); the
/// counts (the refinement's indirect dispatch, then the mask's counters) and their host-visible copy (with the brick
/// pool's counts after them); the refine list (band > 0 only, sized for every coarse voxel: the GPU appends to it);
/// the MaskRegion ("ray mask region", host-visible). Also the last frame's MaskParams.
class GpuRayMask {
public:
  /// What a frame's mask counted (read back after the frame).
  struct Counts {
    std::uint32_t refinedFine = 0, maskedFine = 0, coarse = 0, refineList = 0;
    std::uint32_t outOfView = 0; ///< listed band voxels out of the view's reach (kMaskCountOutOfView)
    std::uint32_t activeBricks = 0, overflowBricks = 0;
    std::uint32_t cutVoxels = 0; ///< refined fine voxels whose walks the loop budget ended (kRefineStatCutVoxels)
    std::uint32_t nearHalf = 0, nearHalfKept = 0; ///< kRefineStatNearHalf, kRefineStatNearHalfKept
    std::uint32_t movedKept = 0; ///< of refinedFine, those kMaskMovedOnly entries kept unwalked (kRefineStatMovedKept)
  };
  /// @param settings the pipeline's settings in effect (band, beta, settling and refresh periods)
  /// @param refineParts the refinement's invocations per listed coarse voxel (refinePartsFor)
  /// @throw VulkanError when a buffer cannot be allocated.
  GpuRayMask(const gpu::VulkanContext& ctx, const GridSpec& coarse, const GridSpec& fine,
             const PipelineSettings& settings, std::uint32_t refineParts);
  /// @brief Record: no coarse voxel has been in the band (construction only; BrickPool::allocate resets it too).
  void recordClear(VkCommandBuffer cmd) const;
  /// @brief The grids moved to @a coarse and @a fine, @a coarseShift coarse voxels from where they were
  ///        (SdfPipeline::scroll): record the refinement's history shifted through @a scratch (by @a shiftPass
  ///        where given: recordGridShift), the voxels that entered new to the band. The grids' tables are relative
  ///        to the corner and stay.
  ///        Before the shift the band's counts lose the voxels that leave (MaskLeavePass), and the settling boxes move
  ///        with the grid, so that the next run may visit only what changed (carriesOverScroll).
  void recordScroll(VkCommandBuffer cmd, const GridSpec& coarse, const GridSpec& fine, const glm::ivec3& coarseShift,
                    const gpu::Buffer& scratch, const GridShiftPass* shiftPass);
  /// @brief Whether the next run may visit only the coarse blocks of what changed (kMaskBlockList) although the grids
  ///        scrolled: one scroll since the last run, and grids whose every coarse voxel's fine voxels lie in one brick
  ///        that moves with it (the fine grid r times the coarse one, r dividing RTSDF_BRICK), so that the kept
  ///        voxels' counts in the bricks and the band moved with them.
  bool carriesOverScroll() const { return mExactCover && mScrollsSinceRun == 1; }
  /// @brief From the next mask on, refine only the band within @a reach (world units; null: the whole band).
  void setViewReach(const ViewReach* reach);
  /// @brief MaskCompactPass's parameters for frame number @a frame with @a movedBoxes moving instances and the
  ///        flags @a flags (kMaskRelistOutOfView, kMaskCoarseRebuilt).
  gpu::shared::MaskParams params(std::uint32_t frame, std::uint32_t movedBoxes, int flags = 0) const;
  /// @brief Record frame number @a frame's mask: the counters reset (with @a pool's), then, where band > 0,
  ///        MaskRegionPass and MaskCompactPass over the coarse SDF @a coarse, the moved boxes @a movedBoxes
  ///        (@a movedCount of them) and the coarse SDF's ChangedBox @a changedBox, with @a flags (params), and
  ///        @a pool's BrickAllocPass; then MaskDispatchPass. With kMaskRegionOnly in @a flags the run visits only what
  ///        can change (the band's and the bricks' counts are kept), @a near the coarse voxels a moving box comes
  ///        within the band's reach of (movedReachBox). The parameters become lastParams().
  ///        With kMaskBlockList too (after a scroll: carriesOverScroll) it visits the coarse blocks that the changed
  ///        voxels' marks @a changedBlocks (CoarseSdfBuilder::changedBlocksBuffer) reach, those that entered with
  ///        the scroll, the last run's settling box and @a near (UpsampleBlocksPass lists them).
  void recordMask(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, std::uint32_t frame, std::uint32_t movedCount,
                  const gpu::Buffer& coarse, const gpu::Buffer& movedBoxes, const gpu::Buffer& changedBox, int flags,
                  const BrickPool& pool, const CoarseVoxelBox& near = {},
                  const gpu::Buffer* changedBlocks = nullptr);
  /// @brief The coarse voxels the last run visited: its MaskRegion's, or its listed blocks'. The frame must be
  ///        finished.
  std::uint64_t lastVisitedVoxels() const;
  /// @brief The region the last run of the mask visited (MaskRegion, host-visible). The frame must be finished.
  gpu::shared::MaskRegion lastRegion() const;
  /// @brief Record: the mask's and @a pool's counts copied into the host-visible copy, visible to the host after
  ///        the frame.
  void recordCountsReadback(VkCommandBuffer cmd, const BrickPool& pool) const;
  /// @brief What the last frame counted. The frame must be finished.
  /// @throw Error when the counts exceed what the grids hold (a bug).
  Counts counts() const;

  /// @brief The coarse voxels the last frame (number @a frame; 0: none yet) listed for refinement, expanded into the
  ///        fine voxels under each and sorted, kMaskFineFresh on those new to the band. The frame must be finished.
  std::vector<std::uint32_t> readRefinedVoxels(std::uint32_t frame) const;
  /// @brief As readRefinedVoxels, the band voxels the last frame listed out of the view's reach (their fine voxels
  ///        took the coarse SDF again: outOfViewRewritten), kMaskOutOfView on each.
  std::vector<std::uint32_t> readRewrittenVoxels(std::uint32_t frame) const;
  /// @brief The coarse linear indices the last frame (number @a frame) listed for motion alone (kMaskMovedOnly),
  ///        sorted.
  std::vector<std::uint32_t> readMovedOnlyCoarse(std::uint32_t frame) const;
  /// @brief The fine voxels of every band voxel the last frame (number @a frame) left out of the view's reach (the
  ///        coarse state says so: in the band that frame, no refinements), packed without flags, sorted.
  std::vector<std::uint32_t> readOutOfViewVoxels(std::uint32_t frame) const;
  /// @brief The refinement's history per coarse voxel (read back). The frame must be finished.
  std::vector<glm::uvec2> readCoarseState() const;

  /// @brief MaskParams::reachPad: beta, a coarse voxel's diagonal and a fine voxel, the slack between a coarse
  ///        cell's bound of the distance and its fine voxels (what a moving instance's swept box must come within).
  double reachPad() const;
  const gpu::shared::MaskParams& lastParams() const { return mLastParams; }
  const gpu::Buffer& countsBuffer() const { return mCounts; }
  /// @brief The refinement's kRefineStat* words, zeroed with the counts and read back with them.
  const gpu::Buffer& refineStats() const { return mRefineStats; }
  const gpu::Buffer& refineList() const { return mRefineList; }
  const gpu::Buffer& fineRanges() const { return mFineRanges; }
  const gpu::Buffer& fineToCoarse() const { return mFineToCoarse; }
  const gpu::Buffer& coarseState() const { return mCoarseState; }

private:
  /// The refine list's entries of the last frame with (@a outOfView) or without kMaskOutOfView, expanded.
  std::vector<std::uint32_t> readListedVoxels(std::uint32_t frame, bool outOfView) const;
  /// The refine list's entries of the last frame (number @a frame), as the GPU appended them.
  std::vector<std::uint32_t> readRefineList(std::uint32_t frame) const;
  const gpu::VulkanContext& mCtx;
  GridSpec mCoarseSpec, mFineSpec;
  bool mViewLimited = false;
  ViewReach mView;
  double mBand, mBeta;
  std::uint32_t mSettleFrames, mRefreshPeriod, mRefineParts;
  glm::ivec3 mBrickDims;
  /// The boxes of a run over listed blocks (host-written), written from the last run's settling box and the scroll's.
  void writeListBoxes(std::uint32_t frame, const CoarseVoxelBox& near) const;
  MaskCompactPass mCompact;
  MaskDispatchPass mDispatch;
  MaskRegionPass mRegionPass;
  MaskLeavePass mLeave;
  UpsampleBlocksPass mLister;
  /// A run over listed blocks: its boxes (host-written), its list and a host copy of the list's header, and per axis
  /// each block's first coarse voxel (upsampleBlockFineBegins' layout: the list's total counts coarse voxels).
  gpu::Buffer mListBoxes, mBlockList, mBlockListHeader, mCoarseBegins;
  bool mLastListed = false;  ///< the last run visited listed blocks
  bool mExactCover = false;  ///< the grids as carriesOverScroll needs them
  int mScrollsSinceRun = 0;  ///< scrolls since the last run
  std::vector<CoarseVoxelBox> mEnteredBoxes; ///< the voxels the last scroll brought in
  gpu::Buffer mCoarseState, mFineToCoarse, mFineRanges, mCounts, mRefineStats, mCountsReadback, mRefineList;
  gpu::Buffer mRegion; ///< MaskRegion (host memory: lastRegion() reads it mapped)
  gpu::shared::MaskParams mLastParams{};
};

} // namespace rtsdf
