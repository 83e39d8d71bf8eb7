#pragma once
/// @file PipelineProbe.h
/// @brief Read-backs of an SdfPipeline's internal state, for tests that check the GPU against the CPU references
///        (the brick pool's slots and values, the refinement's history and list, the mask's parameters and moved
///        boxes). Kept out of SdfPipeline.h so that its users see no gpu::shared types.
#include "sdf/coarse/CoarseParams.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/mask/MaskParams.h"
#include "sdf/refine/RefineParams.h"
#include "sdf/SdfPipeline.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief A view of one SdfPipeline's parts. Owns nothing; the pipeline must outlive it. Each read-back waits for a
///        frame in flight first.
class PipelineProbe {
public:
  explicit PipelineProbe(const SdfPipeline& pipeline) : mPipe(pipeline) {}
  /// @brief Per brick of the fine grid (x fastest, SdfPipeline::brickDims()): its slot in the pool, kNoBrick where it
  ///        has none (read back).
  std::vector<std::uint32_t> brickSlots() const;
  /// @brief The pool's values, slot after slot (kBrickVoxels each; read back): the refinement's, for the voxels
  ///        of a slotted brick under the band (the others hold nothing meaningful).
  std::vector<float> brickValues() const;
  /// @brief The fine voxels the last frame refined (MaskCompactPass's refine list, read back, expanded into the
  ///        fine voxels under each coarse voxel and sorted): packed 10 bits per axis, with
  ///        gpu::shared::kMaskFineFresh on those new to the band.
  std::vector<std::uint32_t> refinedVoxels() const;
  /// @brief The coarse voxels (linear indices, sorted) the last frame listed for motion alone (kMaskMovedOnly).
  std::vector<std::uint32_t> movedOnlyCoarse() const;
  /// @brief The fine voxels out of the view's reach the last frame wrote again (GpuRayMask::readRewrittenVoxels).
  std::vector<std::uint32_t> rewrittenVoxels() const;
  /// @brief Per coarse voxel (x fastest): the mask's run that last visited it in the band and its refinements in a
  ///        row (read back; kNotInBand in both before it has been in the band and once it left).
  std::vector<glm::uvec2> coarseState() const;
  /// @brief MaskCompactPass's parameters in the last frame and the moving boxes it read (maskDecisionsCpu's input).
  const gpu::shared::MaskParams& lastMaskParams() const;
  const std::vector<gpu::shared::MovedBox>& lastMovedBoxes() const;
  /// @brief The coarse SDF's block bounds as the last frame left them (CoarseSdfBuilder::readBlockMax).
  std::vector<std::uint32_t> coarseBlockMax() const;
  /// @brief The coarse seeds as the last frame or scroll left them (CoarseSdfBuilder::readSeeds): VoxelizePass's
  ///        output where the pipeline keeps its transform (coarseBuiltOverChanges).
  std::vector<std::uint32_t> coarseSeeds() const;
  /// @brief The region of the last coarse build over what changed (CoarseSdfBuilder::readRegionLists), and whether
  ///        the last frame's coarse build was one.
  CoarseRegionLists coarseRegion() const;
  bool coarseOverChange() const;
  /// @brief Per coarse block, the changedBlockReach bits of its voxels the last coarse build changed
  ///        (CoarseSdfBuilder::readChangedBlocks), and the blocks the last upsampling over blocks listed (sorted;
  ///        empty where it upsampled the whole grid or nothing).
  std::vector<std::uint32_t> changedCoarseBlocks() const;
  std::vector<std::uint32_t> upsampledBlocks() const;
  /// @brief The coarse voxels the last run of the mask visited (GpuRayMask::lastRegion).
  gpu::shared::MaskRegion lastMaskRegion() const;

private:
  const SdfPipeline& mPipe;
};

/// @brief Failures injected into one SdfPipeline, for tests of what a frame does after one. The pipeline must outlive
///        it.
class PipelineFaults {
public:
  explicit PipelineFaults(SdfPipeline& pipeline) : mPipe(pipeline) {}
  /// @brief The next submitFrame() throws Error after recording its coarse SDF, its other passes unrecorded and
  ///        nothing submitted (as a device out of memory would leave it).
  void failNextRecording() { mPipe.mFailNextRecording = true; }
  /// @brief The next scroll() throws Error after recording its shifts, nothing submitted (its checks passed).
  void failNextScroll() { mPipe.mFailNextScroll = true; }

private:
  SdfPipeline& mPipe;
};

} // namespace rtsdf
