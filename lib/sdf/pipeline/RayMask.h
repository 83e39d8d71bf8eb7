#pragma once
/// @file RayMask.h
/// @brief The ray mask as the host sees it (RayMask: the coarse band's OpenVDB mirror and the fine voxels under it)
///        built from a dense coarse SDF (buildRayMask). The GPU's side of it is GpuRayMask's.
#include "grid/GridSpec.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief The ray mask: the coarse SDF mirrored into OpenVDB (active exactly where |c| <= d) and the fine
///        voxels whose centres lie in active coarse voxels (maskFineRanges), packed 10 bits per axis, sorted.
struct RayMask {
  /// The mirror (null when d = 0: nothing is refined). Its transform is the coarse grid's; where the coarse
  /// voxels are smaller than OpenVDB accepts (minVdbVoxelSize()), the mirror is measured in voxels (voxel
  /// size 1, values and background divided by h) and covers the same voxels.
  openvdb::FloatGrid::Ptr coarse;
  std::vector<std::uint32_t> fineVoxels;
  std::uint64_t coarseVoxels = 0; ///< active coarse voxels
};

/// @brief The ray mask of a dense coarse SDF (x fastest): the CPU reference of what MaskCompactPass counts and
///        lists on the GPU, and what SdfPipeline::rayMask() builds on demand from the coarse SDF read back.
RayMask buildRayMask(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                     double band);

} // namespace rtsdf
