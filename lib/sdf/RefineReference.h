#pragma once
/// @file RefineReference.h
/// @brief CPU reference of the refinement passes: the same trilinear upsampling and, for a fresh frame, the
///        same ray sampling (the same PCG random directions) as refine_upsample.comp and refine.comp, with
///        Embree's rtcIntersect1 for the rays.
#include "gpu/shared/Refine.h"
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief The coarse SDF trilinearly upsampled at the centre of fine voxel @a v (clamped at the borders).
float upsampleCoarse(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                     const glm::ivec3& v);

/// @brief One fresh frame (no history) of rays-mode refinement at the packed fine voxels @a mask:
///        f = min(c + beta + sqrt(3)/2 h_coarse, nearest hit), signed by the majority of back-face hits
///        (rays of unlimited reach, as refine.comp). The grids are in world coordinates; positions are computed
///        in @a geometry's frame (SceneGeometry::origin), as SdfPipeline does.
std::vector<float> refineRaysCpu(const SceneGeometry& geometry, const std::vector<float>& coarse,
                                 const GridSpec& coarseSpec, const GridSpec& fineSpec,
                                 const std::vector<std::uint32_t>& mask, std::uint32_t rays, std::uint32_t frame,
                                 std::uint32_t seed, float beta);

/// @brief What MaskCompactPass decides in one frame of incremental refinement.
struct MaskDecisions {
  std::vector<std::uint32_t> refined; ///< fine voxels to refine, packed with kMaskFineFresh, sorted
  std::vector<glm::uvec2> state;      ///< per coarse voxel: (last frame in the band, refinements in a row) after
};

/// @brief CPU reference of MaskCompactPass's incremental decisions: for every coarse voxel of @a coarse (dense,
///        x fastest) in the band (|c| <= p.band), gpu::shared::refinesThisFrame with its state from @a state and
///        the boxes @a moved; the fine voxels of those refined (maskFineRanges), and the state advanced.
/// @param coarseSpec, fineSpec the grids; @a p as the pass ran (coarse corner in the GPU's frame, p.movedBoxes
///        ignored: all of @a moved are read).
MaskDecisions maskDecisionsCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                               std::vector<glm::uvec2> state, const gpu::shared::MaskParams& p,
                               const std::vector<gpu::shared::MovedBox>& moved);

/// @brief CPU reference of the bricks MaskCompactPass stamps: the linear indices (x fastest, bricks of RTSDF_BRICK^3
///        fine voxels) of the bricks holding a fine voxel under a coarse voxel of @a coarse with |c| <= @a band
///        (maskFineRanges), sorted. Empty for band <= 0.
std::vector<std::uint32_t> bandBricksCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec,
                                         const GridSpec& fineSpec, double band);

/// @brief CPU reference of UpsamplePass on the sparse state: the dense fine SDF (x fastest) from the coarse SDF
///        @a coarse and the brick pool. A fine voxel under a coarse voxel with |c| <= @a band whose brick has a
///        slot in @a brickSlots takes @a poolValues[slot * kBrickVoxels + its place in the brick]; every other
///        voxel the coarse SDF upsampled (upsampleCoarse). The grids as the GPU sees them (the same floats).
std::vector<float> resolveFineCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec,
                                  const GridSpec& fineSpec, float band, const std::vector<std::uint32_t>& brickSlots,
                                  const std::vector<float>& poolValues);

} // namespace rtsdf
