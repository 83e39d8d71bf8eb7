#pragma once
/// @file MaskCpu.h
/// @brief CPU copies of the ray mask's decisions (MaskCompactPass): the same shared functions
///        (sdf/mask/MaskParams.h) on the same tables (maskFineRanges), so the outputs must be identical.
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseParams.h"
#include "sdf/mask/MaskParams.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief What MaskCompactPass decides in one frame of incremental refinement.
struct MaskDecisions {
  std::vector<std::uint32_t> refined; ///< fine voxels to refine, packed with kMaskFineFresh, sorted
  std::vector<glm::uvec2> state;      ///< per coarse voxel: (the run that last visited it in the band or kNotInBand,
                                      ///< refinements in a row) after
  std::vector<std::uint32_t> rewritten; ///< fine voxels out of the view's reach written again with the coarse SDF
                                        ///< (outOfViewRewritten), packed with kMaskOutOfView, sorted
  std::vector<std::uint32_t> movedOnly; ///< coarse linear indices of those refined for motion alone
                                        ///< (refinedForMotionAlone: kMaskMovedOnly), sorted
};

/// @brief CPU copy of MaskCompactPass's incremental decisions: for every coarse voxel of @a coarse (dense,
///        x fastest) in the band (|c| <= p.band), gpu::shared::refinesThisFrame with its state from @a state and
///        the boxes @a moved, or out of the view's reach (withinViewReach) none; the fine voxels of those refined
///        and of those out of view written again (outOfViewRewritten, where the coarse SDF changed: @a changed),
///        (maskFineRanges), and the state advanced.
///        A voxel that left the band takes the state kNotInBand.
/// @param coarseSpec, fineSpec the grids; @a p as the pass ran (coarse corner in the GPU's frame, p.movedBoxes
///        ignored: all of @a moved are read).
/// @param visit where given, the voxels of its box alone (MaskRegion, a run over what changed); the others keep
///        their state and are neither refined nor written.
MaskDecisions maskDecisionsCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                               std::vector<glm::uvec2> state, const gpu::shared::MaskParams& p,
                               const std::vector<gpu::shared::MovedBox>& moved,
                               const gpu::shared::ChangedBox& changed = {glm::uvec4(gpu::shared::kChangedBoxEmptyLo),
                                                                          glm::uvec4(0u)},
                               const gpu::shared::MaskRegion* visit = nullptr);

/// @brief CPU copy of the bricks MaskCompactPass stamps: the linear indices (x fastest, bricks of RTSDF_BRICK^3
///        fine voxels) of the bricks holding a fine voxel under a coarse voxel of @a coarse with |c| <= @a band
///        (maskFineRanges), sorted. Empty for band <= 0.
std::vector<std::uint32_t> bandBricksCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec,
                                         const GridSpec& fineSpec, double band);

} // namespace rtsdf
