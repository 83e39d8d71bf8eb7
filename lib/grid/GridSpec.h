#pragma once
/// @file GridSpec.h
/// @brief The voxel grid a field is sampled on: bounds, voxel size, per-axis dims, cell-centred mapping.
#include "util/Bounds.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace rtsdf {

/// @brief A cell-centred voxel grid with cubic voxels.
///
/// Voxel (i, j, k) covers [origin + (i, j, k) * h, origin + (i+1, j+1, k+1) * h] and its sample sits at the
/// centre, origin + (i + 1/2, j + 1/2, k + 1/2) * h. Dims are any positive sizes (not only cubes or powers of
/// two). The OpenVDB transform of this grid is scale h plus a translation to the first voxel's centre, so
/// OpenVDB's indexToWorld(ijk) lands on the same point.
struct GridSpec {
  glm::dvec3 origin{0.0}; ///< world-space corner of voxel (0, 0, 0)
  double voxelSize = 1.0; ///< edge length h of a (cubic) voxel
  glm::ivec3 dims{1};     ///< voxels along x, y, z

  /// @brief World position of voxel @a ijk's centre.
  glm::dvec3 indexToWorld(const glm::dvec3& ijk) const { return origin + (ijk + 0.5) * voxelSize; }
  /// @brief Continuous index of a world position (voxel centres at whole numbers).
  glm::dvec3 worldToIndex(const glm::dvec3& p) const { return (p - origin) / voxelSize - 0.5; }
  /// @brief The world box the voxels cover.
  Bounds bounds() const { return {origin, origin + glm::dvec3(dims) * voxelSize}; }
  std::uint64_t voxelCount() const { return std::uint64_t(dims.x) * std::uint64_t(dims.y) * std::uint64_t(dims.z); }
  /// @brief Linear index of a voxel, x fastest.
  std::uint64_t linear(int i, int j, int k) const {
    return (std::uint64_t(k) * std::uint64_t(dims.y) + std::uint64_t(j)) * std::uint64_t(dims.x) + std::uint64_t(i);
  }
  bool contains(const glm::ivec3& ijk) const {
    return ijk.x >= 0 && ijk.y >= 0 && ijk.z >= 0 && ijk.x < dims.x && ijk.y < dims.y && ijk.z < dims.z;
  }
  std::string describe() const;
  /// @brief The same voxels with coordinates measured from the world point @a frameOrigin (origin - frameOrigin,
  ///        in double): the grid as the GPU passes see it in their frame.
  GridSpec inFrame(const glm::dvec3& frameOrigin) const {
    GridSpec s = *this;
    s.origin -= frameOrigin;
    return s;
  }

  /// @brief The grid that covers @a bounds grown by @a padding on every side, with voxels of size
  ///        (longest side of @a bounds) / @a resolution; every axis gets as many voxels as it needs (at
  ///        least one), and the grid is centred on the padded box.
  /// @param bounds     world box to cover (finite, not empty; may be flat along some axes; a single point
  ///                   needs padding > 0, and then the padded box sets the voxel size)
  /// @param resolution voxels across the longest side of @a bounds (padding adds voxels), in
  ///                   [1, kMaxResolution]
  /// @param padding    world-space margin added on each side, finite and >= 0
  /// @throw Error on empty or non-finite bounds, a zero-size box, a resolution or padding out of range, or a
  ///        padding that makes an axis longer than 4 x kMaxResolution voxels.
  static GridSpec fromBounds(const Bounds& bounds, int resolution, double padding);

  /// @brief The length of the grid's diagonal: no distance inside the grid is longer.
  double diagonal() const { return glm::length(glm::dvec3(dims)) * voxelSize; }

  /// @brief The largest resolution accepted along one axis.
  static constexpr int kMaxResolution = 8192;
};

/// @brief Refuse grids whose dense storage at @a bytesPerVoxel would exceed @a maxBytes (before allocating).
/// @throw Error naming @a what, the grid and the memory it would need.
void checkDenseMemory(const GridSpec& spec, std::size_t bytesPerVoxel, std::uint64_t maxBytes, const std::string& what);

} // namespace rtsdf
