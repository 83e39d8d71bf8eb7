#pragma once
/// @file RefineCpu.h
/// @brief CPU copies of the refinement passes: the same trilinear upsampling and, for a fresh frame, the
///        same ray sampling (the same PCG random directions) as refine_upsample_main.glsl and refine_main.glsl, with
///        Embree's rtcIntersect1 for the rays.
///        The mask's CPU copies (MaskCpu.h) come with them: the refinement runs on its decisions.
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"
#include "sdf/mask/MaskCpu.h"
#include "sdf/refine/RefineParams.h"
#include "sdf/scenebvh/ClosedPieces.h"

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief The coarse SDF trilinearly upsampled at the centre of fine voxel @a v (clamped at the borders).
float upsampleCoarse(const std::vector<float>& coarse, const GridSpec& coarseSpec, const GridSpec& fineSpec,
                     const glm::ivec3& v);

/// @brief One fresh frame (no history) of rays-mode refinement at the packed fine voxels @a mask:
///        f = min(c + beta + sqrt(3)/2 h_coarse, nearest hit), signed by the majority of back-face hits
///        (rays of unlimited reach, as refine.comp). The grids are in world coordinates; positions are computed
///        in @a geometry's frame (SceneGeometry::origin), as SdfPipeline does. Where the votes say outside, a voxel
///        inside a closed piece that overlaps another is inside (@a pieces, for the same scene, moment and frame;
///        null: the votes alone).
std::vector<float> refineRaysCpu(const SceneGeometry& geometry, const std::vector<float>& coarse,
                                 const GridSpec& coarseSpec, const GridSpec& fineSpec,
                                 const std::vector<std::uint32_t>& mask, std::uint32_t rays, std::uint32_t frame,
                                 std::uint32_t seed, float beta, const ClosedPieceUnionCpu* pieces = nullptr);

/// @brief CPU copy of UpsamplePass on the sparse state: the dense fine SDF (x fastest) from the coarse SDF
///        @a coarse and the brick pool. A fine voxel under a coarse voxel with |c| <= @a band whose brick has a
///        slot in @a brickSlots takes @a poolValues[slot * kBrickVoxels + its place in the brick]; every other
///        voxel the coarse SDF upsampled (upsampleCoarse). The grids as the GPU sees them (the same floats).
std::vector<float> resolveFineCpu(const std::vector<float>& coarse, const GridSpec& coarseSpec,
                                  const GridSpec& fineSpec, float band, const std::vector<std::uint32_t>& brickSlots,
                                  const std::vector<float>& poolValues);

/// @brief CPU copy of CoarseDistancePass's changed-block marks: per block (coarseBlockIndex) of a coarse grid of
///        @a dims, changedBlockReach of each voxel whose value differs, bit for bit, between @a before and @a after.
std::vector<std::uint32_t> changedBlockMarksCpu(const std::vector<float>& before, const std::vector<float>& after,
                                                const glm::ivec3& dims);

/// @brief CPU copy of UpsampleBlocksPass's listing: the blocks (coarseBlockIndex, ascending) of a coarse grid of
///        @a dims that a block within one of them holds a changed voxel reaching (@a marks), or that meet one of
///        @a boxes grown by a voxel.
std::vector<std::uint32_t> upsampleBlocksCpu(const std::vector<std::uint32_t>& marks, const glm::ivec3& dims,
                                             const gpu::shared::UpsampleBoxes& boxes);

} // namespace rtsdf
