#pragma once
/// @file CoarseScroll.h
/// @brief What a coarse grid that scrolled by whole voxels keeps and what its next build must redo: the seed lattice
///        that makes a kept seed equal a full build's (seedLatticeCell), the voxels that stayed and those that entered
///        (keptByShift, boxesOutside), the change boxes of the transform (scrollChanges) and the voxels whose upsampling
///        a scroll invalidates whatever their value (scrollUpsampleBoxes). Used by CoarseSdfBuilder::recordScroll and
///        record(), and by FieldPasses.
#include "grid/GridSpec.h"
#include "sdf/coarse/CoarseSdf.h"

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace rtsdf {

/// @brief The cells of a seed lattice a grid may reach from its origin (seedLatticeCell): there the triangles'
///        float cell coordinates keep 1/64 of a voxel.
inline constexpr int kSeedLatticeCells = 1 << 17;

/// @brief The cell of the lattice of @a coarse's voxel size from the world's origin that @a coarse's corner is, where
///        it is one exactly (a cascade level's corner is: CascadeLayout snaps it) and the grid lies within
///        kSeedLatticeCells of that origin; none otherwise.
std::optional<glm::ivec3> seedLatticeCell(const GridSpec& coarse);

/// @brief The disjoint boxes that cover the voxels of a grid of @a dims outside @a kept (a box inside the grid, or
///        empty: then the whole grid), at most six: the slabs along x beyond it, then along y within its x range,
///        then along z within its x and y ranges. After a scroll they are the voxels that entered.
std::vector<CoarseVoxelBox> boxesOutside(const glm::ivec3& dims, const CoarseVoxelBox& kept);

/// @brief The same outside @a kept within the box @a grid (which may lie anywhere).
std::vector<CoarseVoxelBox> boxesOutside(const CoarseVoxelBox& grid, const CoarseVoxelBox& kept);

/// @brief The voxels of a grid of @a dims that keep their seeds when it scrolls by @a shift voxels (voxel v takes
///        v + shift's): those for which v + shift lies in the grid; empty where the shift is the grid's size or more.
CoarseVoxelBox keptByShift(const glm::ivec3& dims, const glm::ivec3& shift);

/// @brief The change boxes of a build after a grid of @a dims scrolled by @a shift voxels, in the new grid's voxels:
///        the box of the voxels that entered, and the box of the old voxels that left it (beyond the grid), whose
///        seeds left with them (the voxels whose nearest seed was one are those that box reaches).
std::vector<CoarseVoxelBox> scrollChanges(const glm::ivec3& dims, const glm::ivec3& shift);

/// @brief The coarse voxels of a grid of @a dims, after it scrolled by @a shift voxels, near which the upsampled fine
///        SDF must be written again although their coarse values may be the same as before the scroll: the voxels that
///        entered (boxesOutside of keptByShift: the fine voxels under them hold their neighbours' values, the dense
///        fine SDF's shift being loose), and the layer at each face the grid moved away from (a fine voxel within half
///        a coarse voxel of a face takes the face's value, clamped, where it used to blend with the voxel beyond it).
///        Grown by the upsampling's stencil (upsampleRegionOf), they and the coarse voxels whose value changed hold
///        every fine voxel whose upsampled value differs from its shifted one. Empty for no shift; the whole grid for a
///        shift of its size or more.
std::vector<CoarseVoxelBox> scrollUpsampleBoxes(const glm::ivec3& dims, const glm::ivec3& shift);

} // namespace rtsdf
