#pragma once
/// @file ToroidalLevelCpu.h
/// @brief The CPU reference of a cascade level's toroidal (wrap-around) update: when the camera moves the level by m
///        coarse voxels, only the slabs that entered are voxelized and only the voxels whose clamped distance can have
///        changed are transformed again, in place. The GPU voxelizes so (a scrolled level's seeds move with it:
///        CoarseSdfBuilder::recordScroll) but transforms its whole grid again; this is the rule its transform must
///        follow and the test it must pass (equal to a full rebuild, voxel for voxel).
#include "sdf/cascade/CascadeLayout.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief One level's coarse state on the CPU: per voxel whether a triangle touches it (a seed) and the distance to
///        the nearest seed in coarse voxels, clamped to maxVoxels (as a global distance field clamps each clipmap's
///        distances), so a voxel's value depends only on the seeds within maxVoxels of it. Storage is toroidal: the
///        voxel at world lattice cell w lives at slot w mod N, whatever the level's position.
class ToroidalLevelCpu {
public:
  /// @param triangles world-space corners, 3 per triangle (w ignored)
  /// @param maxVoxels the clamp of the distance, in coarse voxels (>= 1)
  ToroidalLevelCpu(std::vector<glm::dvec3> triangles, int maxVoxels);

  /// @brief Build the level at @a level from scratch (every voxel voxelized and transformed).
  void rebuild(const CascadeLevel& level);
  /// @brief Move to @a level (the same level index and shape, centred elsewhere): the slabs that entered are
  ///        voxelized; the voxels within maxVoxels of an entered slab or of a face the level moved away from are
  ///        transformed again; the rest is kept. Falls back to rebuild() when the move is at least the grid's size.
  void moveTo(const CascadeLevel& level);
  /// @brief The clamped distances in the level's own order (x fastest from its corner), as a full rebuild lays them.
  std::vector<float> distances() const;
  /// @brief The seeds (1 where a triangle touches the voxel) in the level's own order.
  std::vector<std::uint8_t> seeds() const;
  /// @brief Voxels voxelized and voxels transformed by the last rebuild() or moveTo().
  std::uint64_t voxelizedLast() const { return mVoxelized; }
  std::uint64_t transformedLast() const { return mTransformed; }

private:
  using Cell = glm::i64vec3;
  std::size_t slot(const Cell& world) const;
  /// Voxelize the world cells in [lo, hi) (within the level) into their slots.
  void voxelize(const Cell& lo, const Cell& hi);
  /// Recompute the clamped distance of the world cells in [lo, hi), clipped to the level.
  void transform(Cell lo, Cell hi);
  std::vector<glm::dvec3> mTriangles;
  int mMaxVoxels;
  double mVoxel = 0.0;          ///< the level's coarse voxel
  int mN = 0;                   ///< voxels per axis
  Cell mCorner{0};              ///< the level's corner in world lattice cells
  std::vector<std::uint8_t> mSeed;
  std::vector<float> mDistance;
  std::uint64_t mVoxelized = 0, mTransformed = 0;
};

} // namespace rtsdf
