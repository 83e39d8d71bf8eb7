#pragma once
/// @file FieldPasses.h
/// @brief The passes that compute one pipeline's fields on its pair of grids: the coarse SDF (CoarseSdfBuilder), the
///        refinement of the masked fine voxels (RayRefinePass or ClosestRefinePass, then WindingExactPass where an
///        open mesh's winding number lay near 1/2) and the upsampling into the dense fine SDF (UpsamplePass), with
///        what they write besides the brick pool.
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "sdf/refine/RefineParams.h"
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/scenebvh/GpuSceneBvh.h"
#include "sdf/PipelineSettings.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/pipeline/BrickPool.h"
#include "sdf/pipeline/DenseFineWrites.h"
#include "sdf/pipeline/GpuRayMask.h"

#include <array>
#include <memory>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief The field passes of one pair of grids. Owns the passes (the coarse builder with its buffers, the coarse SDF
///        among them), the dense fine SDF (FineStorage::Dense only: "fine SDF") and the frame's RefineParams for
///        shading passes that sample the bricks ("brick sampling parameters").
class FieldPasses {
public:
  /// @param settings the settings in effect (mode, closest search, band, alpha, beta, rays, seed, fine storage)
  /// @param parts the refinement's boxes per coarse voxel (refinePartsFor)
  /// @param closest the shader variant of ClosestRefinePass (closest mode)
  /// @throw VulkanError when a buffer cannot be allocated or a shader is missing.
  FieldPasses(const gpu::VulkanContext& ctx, const GridSpec& coarse, const GridSpec& fine,
              const PipelineSettings& settings, const RefineParts& parts,
              const ClosestRefinePass::Variant& closest);
  /// @brief Record: the dense fine SDF zeroed, where there is one (construction only).
  void recordClear(VkCommandBuffer cmd) const;
  /// @brief Record the coarse SDF of @a bvh's instanced triangles into coarseBuffer() (scopes to @a profiler, null:
  ///        none); where @a change is given, over what a change of seeds inside it reaches (CoarseSdfBuilder::record:
  ///        taken after a full build of these settings where coarseBuiltOverChanges says so). The frame's recordFine
  ///        takes what a scroll since the last one left to upsample.
  /// @throw Error as CoarseSdfBuilder::record does.
  void recordCoarse(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const GpuSceneBvh& bvh,
                    const CoarseVoxelBox* change = nullptr);
  /// @brief Whether the last recordCoarse built over what changed.
  bool lastCoarseOverChange() const { return mCoarse.lastBuiltOverChange(); }
  /// @brief Whether the scroll since the last recordCoarse moved the coarse SDF with the grids
  ///        (CoarseSdfBuilder::scrollMovedDistances), so that the next frame's upsampling may run over what changed.
  bool scrollMovedCoarse() const { return mCoarse.scrollMovedDistances(); }
  /// The coarse voxels whose seeds the last coarse build voxelized.
  std::uint64_t lastCoarseVoxelized() const { return mCoarse.lastVoxelizedVoxels(); }
  /// @brief Read back the region of the last recordCoarse over what changed. The frame must be finished.
  gpu::shared::CoarseRegion readCoarseRegion() const { return mCoarse.readRegion(); }
  CoarseRegionLists readCoarseRegionLists() const { return mCoarse.readRegionLists(mCoarseSpec.dims); }
  /// @brief Read back the coarse SDF's block bounds (CoarseSdfBuilder::readBlockMax). The frame must be finished.
  std::vector<std::uint32_t> readCoarseBlockMax() const { return mCoarse.readBlockMax(mCoarseSpec.dims); }
  /// @brief Read back the coarse seeds (CoarseSdfBuilder::readSeeds). The frame must be finished.
  std::vector<std::uint32_t> readCoarseSeeds() const { return mCoarse.readSeeds(mCoarseSpec.dims); }
  /// @brief Read back the coarse build's changed-block marks (CoarseSdfBuilder::readChangedBlocks). The frame must be
  ///        finished.
  std::vector<std::uint32_t> readChangedCoarseBlocks() const { return mCoarse.readChangedBlocks(mCoarseSpec.dims); }
  /// @brief The blocks the last upsampling over blocks listed, sorted (empty where it upsampled the whole grid or
  ///        nothing). The frame must be finished.
  std::vector<std::uint32_t> readUpsampledBlocks() const;
  /// @brief The refinement's and upsampling's parameters for frame number @a frame with the brick pool @a pool and
  ///        @a movedBoxes boxes of moving instances (at most RTSDF_MAX_MOVED_BOXES).
  gpu::shared::RefineParams refineParams(std::uint32_t frame, const BrickPool& pool,
                                         std::uint32_t movedBoxes = 0) const;
  /// @brief Record after the mask: where @a refine, the refinement of @a mask's refine list (band > 0); where
  ///        @a upsample, the upsampling into the dense fine SDF (Dense only), of every voxel or, where
  ///        @a upsampleChanged, of the blocks that the coarse voxels the last recordCoarse changed reach
  ///        (UpsampleBlocksPass) and, where a scroll that moved the coarse SDF came before that build, of those near
  ///        the voxels that entered and the faces the grids moved away from (scrollUpsampleBoxes; a scroll that did
  ///        not, or a build not over what changed after it, upsamples every voxel); and @a p uploaded for shading. @a movedBoxes: the moving
  ///        instances' boxes the mask read (p counts them).
  void recordFine(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const gpu::shared::RefineParams& p,
                  const GpuSceneBvh& bvh, const GpuRayMask& mask, const BrickPool& pool,
                  const gpu::Buffer& movedBoxes, bool refine = true, bool upsample = true,
                  bool upsampleChanged = false);
  /// @brief Where the last recordFine wrote the dense fine SDF: its upsampling's blocks (or the whole grid) and, where
  ///        @a refined (it refined), @a mask's refine list; the whole grid where @a whole (a first frame or a scroll:
  ///        the dense fine SDF was cleared or shifted). None without a dense fine SDF.
  DenseFineWrites denseWrites(const GpuRayMask& mask, bool refined, bool whole) const;
  /// @brief The fine voxels the last recordFine's upsampling wrote or kept (the slotted band's): the grid's, or those
  ///        of the listed blocks; 0 where it did not upsample. The frame must be finished.
  std::uint64_t lastUpsampledVoxels() const;
  /// @brief Read back the box of the coarse voxels the last recordCoarse changed (gpu::shared::ChangedBox). The
  ///        frame must be finished.
  gpu::shared::ChangedBox readChangedBox() const;
  /// @brief The coarse SDF's ChangedBox on the GPU, as the last recordCoarse left it.
  const gpu::Buffer& changedBoxBuffer() const;
  /// @brief The last recordCoarse's changed-block marks on the GPU (CoarseSdfBuilder::changedBlocksBuffer).
  const gpu::Buffer& changedBlocksBuffer() const { return mCoarse.changedBlocksBuffer(); }

  /// @brief The grids moved to @a grids (coarse, fine), @a shift coarse voxels from where they were
  ///        (SdfPipeline::scroll): record, through @a scratch, the coarse seeds' and transform's move
  ///        (CoarseSdfBuilder::recordScroll with @a gridShift: none where @a sceneChanged, the level's part of the
  ///        scene cut again) and the dense fine SDF's shift
  ///        (recordGridShift of gridShiftPlanLoose: the voxels that entered hold their neighbours' values until the
  ///        next frame refines or upsamples them).
  void recordScroll(VkCommandBuffer cmd, const std::pair<GridSpec, GridSpec>& grids, const glm::ivec3& shift,
                    const gpu::Buffer& scratch, bool sceneChanged, const GridShiftPass* gridShift);
  /// @brief Whether the fine SDF is kept dense (FineStorage::Dense).
  bool dense() const { return bool(mFine); }
  const gpu::Buffer& coarseBuffer() const { return mCoarse.distanceBuffer(); }
  /// @brief The dense fine SDF (an empty buffer with FineStorage::Sparse).
  const gpu::Buffer& fineBuffer() const { return mFine; }
  const gpu::Buffer& samplingParams() const { return mSamplingParams; }
  /// @brief Read back the coarse SDF (x fastest). The frame must be finished.
  std::vector<float> readCoarse() const;
  /// @brief Read back the dense fine SDF (x fastest). The frame must be finished.
  std::vector<float> readDenseFine() const;

private:
  /// The upsampling of recordFine: of every voxel, or where @a changedOnly of those near what changed.
  void recordUpsample(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const gpu::shared::RefineParams& p,
                      const GpuRayMask& mask, const BrickPool& pool, bool changedOnly);

  const gpu::VulkanContext& mCtx;
  GridSpec mCoarseSpec, mFineSpec;
  PipelineSettings mSettings;
  RefineParts mParts;
  CoarseSdfBuilder mCoarse;
  UpsamplePass mUpsample;
  UpsampleBlocksPass mUpsampleBlocks;
  UpsampleByBlocksPass mUpsampleByBlocks;
  /// Dense only: the listing's boxes (host-written), its list (and a host copy of its header for the statistics) and
  /// the blocks' fine voxels (upsampleBlockFineBegins, as uploaded).
  gpu::Buffer mUpsampleBoxes, mBlockList, mBlockListHeader, mBlockFineBegins;
  std::vector<int> mFineBegins;
  /// What a scroll leaves to the upsampling of the next frame: scrolled since the last recordCoarse, and whether it
  /// moved the coarse SDF (else every voxel is upsampled), with the coarse boxes whose fine voxels it invalidated.
  struct ScrollUpsample {
    bool scrolled = false, coarseMoved = false;
    std::vector<CoarseVoxelBox> boxes; ///< scrollUpsampleBoxes
  };
  ScrollUpsample mScrollPending; ///< since the last recordCoarse
  ScrollUpsample mScrollFrame;   ///< before this frame's recordCoarse, for its recordFine
  enum class Upsampled { None, Whole, Blocks };
  Upsampled mLastUpsample = Upsampled::None;
  gpu::shared::RefineParams mLastParams{}; ///< the last recordFine's
  std::unique_ptr<RefinePass> mRefine; ///< RayRefinePass or ClosestRefinePass, by the mode
  std::unique_ptr<WindingExactPass> mWindingExact; ///< closest mode: the winding numbers near 1/2
  gpu::Buffer mFine, mSamplingParams;
  gpu::Buffer mWindingDoubts; ///< closest mode: the voxels for mWindingExact (kRefineBindingWindingDoubts)
};

} // namespace rtsdf
