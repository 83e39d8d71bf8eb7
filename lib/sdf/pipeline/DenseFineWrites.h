#pragma once
/// @file DenseFineWrites.h
/// @brief Where a frame of an SdfPipeline wrote its dense fine SDF, for the copies of it that follow it (the
///        renderer's 3D texture: VolumeUpdatePass): nowhere, everywhere, or the lists its passes wrote over.
#include "gpu/Resources.h"
#include "sdf/refine/RefineParams.h"

#include <cstdint>

namespace rtsdf {

/// @brief The fine voxels the last frame wrote into the dense fine SDF (FineStorage::Dense). The buffers are the
///        pipeline's own, on the GPU, and hold this frame's lists until the next frame is recorded.
struct DenseFineWrites {
  enum class Extent {
    None,   ///< nothing (every field pass skipped, or no dense fine SDF)
    Whole,  ///< any voxel: the first frame, a pool reset, a scroll, an upsampling of the whole grid
    Listed, ///< the fine voxels of the blocks the upsampling listed and of the coarse voxels the mask listed
  };
  Extent extent = Extent::Whole;
  /// The pipeline's frame number (1, 2, ...; 0 before the first): a copy updated frame by frame must have seen
  /// every frame before this one.
  std::uint32_t frame = 0;
  /// Listed: UpsampleBlocksPass's list (UpsampleBlockListHeader, its dispatch at offset 0, then the blocks) and
  /// upsampleBlockFineBegins of the grids; null where the frame upsampled nothing.
  const gpu::Buffer* blockList = nullptr;
  const gpu::Buffer* blockFineBegins = nullptr;
  /// Listed: the mask's refine list, its counts (the refinement's dispatch at offset 0, then kMaskCountRefineList)
  /// and maskFineRanges of the grids; null where the frame refined nothing.
  const gpu::Buffer* refineList = nullptr;
  const gpu::Buffer* maskCounts = nullptr;
  const gpu::Buffer* fineRanges = nullptr;
  /// The frame's refinement parameters: the grids and the refinement's boxes per listed coarse voxel.
  gpu::shared::RefineParams params{};
};

} // namespace rtsdf
