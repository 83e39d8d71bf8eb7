#pragma once
/// @file BrickPool.h
/// @brief The sparse fine state of one pipeline: per brick of the fine grid its band count and its slot, and the pool
///        of slots that holds the refinement's values and sign votes for the bricks under the band (BrickPool), with
///        its sizing (poolBricksFor).
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "grid/GridSpec.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/pipeline/PipelineMemory.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

class GridShiftPass;

/// @brief Bricks (RTSDF_BRICK voxels per axis) per axis of the fine grid @a fine.
glm::ivec3 brickDimsOf(const GridSpec& fine);

/// @brief The brick pool's capacity for @a activeBricks bricks under the band: half as many again and 64 more (room
///        for the band to grow as instances move before the pool must be regrown), at most every brick of a grid of
///        @a brickDims bricks.
std::uint64_t poolBricksFor(std::uint64_t activeBricks, const glm::ivec3& brickDims);

/// @brief The brick pool of one fine grid and the pass that hands out its slots (BrickAllocPass).
///
/// Owns, per brick of the grid, the band voxels in view over it ("brick band counts", kept by MaskCompactPass) and its
/// slot ("brick slots", kNoBrick: none); the counts (kBrickCount* words), the free stack, and up to
/// RTSDF_BRICK_PAGES pages of values and of votes, each of pageBricks() bricks (pages beyond the pool bound to a
/// placeholder). There is no pool until allocate(); a frame that overflows it notes the size to regrow to
/// (noteFrame, takeRegrowth).
class BrickPool {
public:
  /// @brief The per-brick buffers of @a fine's bricks (uncleared: recordClear()).
  /// @throw VulkanError when a buffer cannot be allocated.
  BrickPool(const gpu::VulkanContext& ctx, const GridSpec& fine);
  /// @brief Record: no brick counted, none holding a slot, the counts zero (construction only).
  void recordClear(VkCommandBuffer cmd) const;
  /// @brief (Re)allocate the pool for @a bricks bricks, every slot free and no brick holding one, and reset
  ///        @a coarseState (the mask's history: every coarse voxel new to the band) in the same submission. No frame
  ///        may be in flight. @a estimate: the pipeline's memory without the pool, checked with it.
  /// @throw SettingError when it needs more than RTSDF_BRICK_PAGES pages of maxStorageBufferRange or does not fit
  ///        the device (checkPipelineMemory).
  void allocate(std::uint64_t bricks, const PipelineMemory& estimate, const gpu::Buffer& coarseState);
  /// @brief Record: the counts' per-frame words zeroed (the free stack's top persists), and where @a bandCounts the
  ///        bricks' band counts (a run of MaskCompactPass over every voxel counts from zero), before MaskCompactPass.
  void recordResetCounts(VkCommandBuffer cmd, bool bandCounts) const;
  /// @brief Record BrickAllocPass, after MaskCompactPass counted the band in the bricks.
  void recordAlloc(VkCommandBuffer cmd, gpu::GpuProfiler* profiler) const;
  /// @brief The grid moved by @a brickShift whole bricks (SdfPipeline::scroll): record the slots shifted
  ///        through @a scratch (by @a shiftPass where given: recordGridShift; the bricks that entered hold no slot),
  ///        and the slots of the bricks that left pushed back on the free stack (read back now: no frame may be in
  ///        flight). The values stay in their slots, so a brick that stays keeps its refinement. The band counts are
  ///        not shifted: the next run of the mask counts them from zero.
  void recordScroll(VkCommandBuffer cmd, const glm::ivec3& brickShift, const gpu::Buffer& scratch,
                    const GridShiftPass* shiftPass);
  /// @brief After a frame that counted @a activeBricks bricks under the band, @a overflowBricks of them without a
  ///        slot: remember to regrow the pool (poolBricksFor) before the next.
  void noteFrame(std::uint64_t activeBricks, std::uint64_t overflowBricks);
  /// @brief The size to regrow to (0: none), forgotten once taken.
  std::uint64_t takeRegrowth();

  /// @brief The device bytes of a pool of @a bricks bricks (values, votes and a free-stack entry each).
  static std::uint64_t deviceBytesFor(std::uint64_t bricks);
  const glm::ivec3& brickDims() const { return mBrickDims; }
  /// @brief Every brick of the grid.
  std::uint64_t gridBricks() const { return std::uint64_t(mBrickDims.x) * mBrickDims.y * mBrickDims.z; }
  /// @brief The pool's capacity in bricks (0 before allocate()).
  std::uint64_t capacity() const { return mPoolBricks; }
  std::uint64_t pageBricks() const { return mPageBricks; }
  /// @brief The pages the refinement binds.
  BrickPages pages() const;
  const gpu::Buffer& bandCounts() const { return mNeeded; }
  const gpu::Buffer& slots() const { return mSlots; }
  const gpu::Buffer& counts() const { return mCounts; }
  /// @brief A small buffer bound where a pass needs one and has none (pages beyond the pool, no dense SDF).
  const gpu::Buffer& placeholder() const { return mPlaceholder; }

  /// @brief Read back the slots, per brick (x fastest, brickDims()). The frame must be finished.
  std::vector<std::uint32_t> readSlots() const;
  /// @brief Read back the values, slot after slot (kBrickVoxels each). The frame must be finished.
  std::vector<float> readValues() const;

private:
  const gpu::VulkanContext& mCtx;
  GridSpec mFineSpec;
  glm::ivec3 mBrickDims;
  BrickAllocPass mAlloc;
  std::uint64_t mPoolBricks = 0, mPageBricks = 0;
  std::uint64_t mGrowTo = 0; ///< > 0: the last frame overflowed; the next one reallocates the pool
  gpu::Buffer mNeeded, mSlots, mFree, mCounts, mPlaceholder;
  gpu::Buffer mValues[RTSDF_BRICK_PAGES], mVotes[RTSDF_BRICK_PAGES];
};

} // namespace rtsdf
