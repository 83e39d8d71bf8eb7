#pragma once
/// @file FieldError.h
/// @brief Accuracy of a distance field against a reference: mean/RMS/max |error| in voxels and the rate
///        of wrong signs, over the voxels active in both.
#include "grid/GridSpec.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief Values within this many voxels of zero are "on the surface": they count toward the distance error
///        but not toward wrong signs (a voxel centre lying on a face, as on axis-aligned walls, has no sign).
constexpr double kOnSurfaceVoxels = 1e-3;

/// @brief A grid's voxel size, the unit of its errors: the cube root of a voxel's volume when its voxels are not
///        cubic.
double voxelUnit(const openvdb::FloatGrid& grid);

/// @brief How the voxels of a grid B sit on those of a grid A.
enum class GridAlignment {
  Same,     ///< equal transforms: voxel (i,j,k) of A is voxel (i,j,k) of B
  Shifted,  ///< the same lattice offset by whole voxels: A's (i,j,k) is B's (i,j,k) + shift
  Resampled ///< any other transform: B is sampled trilinearly at A's voxel centres
};

/// @brief B's voxels relative to A's (matchGrids).
struct GridMatch {
  GridAlignment alignment = GridAlignment::Same;
  openvdb::Coord shift{0, 0, 0}; ///< Shifted: B's index of A's voxel (0,0,0)
  /// @brief One line saying how B is read at A's voxels ("" when the voxels are the same).
  std::string description;
};

/// @brief Match the voxels of @a b to those of @a a: equal transforms, a lattice shifted by whole voxels (within
///        1e-6 voxel), or anything else (resampling).
GridMatch matchGrids(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b);

/// @brief Error statistics of a field against a reference, in voxels of the field's grid.
struct FieldError {
  std::uint64_t voxels = 0;        ///< voxels compared (active in both)
  double meanAbs = 0.0;            ///< mean |a - b| / voxel size
  double rms = 0.0;                ///< sqrt(mean (a - b)^2) / voxel size
  double maxAbs = 0.0;             ///< max |a - b| / voxel size
  std::uint64_t signMismatches = 0;///< voxels where exactly one of a, b is negative, neither on the surface
  std::uint64_t onlyInA = 0;       ///< active in A only
  std::uint64_t onlyInB = 0;       ///< active in B only (resampled: B voxels whose centre is in no active A voxel)
  GridAlignment alignment = GridAlignment::Same; ///< how B was read at A's voxels
  double signErrorRate() const { return voxels ? double(signMismatches) / double(voxels) : 0.0; }
  std::string summary() const;
};

/// @brief Compare two grids over the voxels of @a a where @a b is defined, in @a a's voxels.
/// @details With the same voxels (or a lattice shifted by whole voxels) B's voxel is read as it is and "defined"
///          means active. Otherwise B is sampled trilinearly (OpenVDB's BoxSampler) at A's voxel centres, and is
///          defined where all 8 voxels of the stencil are active in B (no inactive ±background value leaks in).
/// @note The unit of the error is A's voxel size (the cube root of a voxel's volume when A's are not cubic).
FieldError compareFields(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b);

/// @brief Compare the active voxels of @a field with @a reference evaluated at their world positions.
/// @param ignoreWithin skip voxels whose reference |distance| is below this (world units), e.g. to
///        exclude the ambiguous zero crossing from sign statistics; 0 keeps all.
FieldError compareWithFunction(const openvdb::FloatGrid& field,
                               const std::function<double(const openvdb::Vec3d&)>& reference,
                               double ignoreWithin = 0.0);

/// @brief Compare a dense field with a reference grid over every voxel active in the reference.
/// @details Unlike compareFields on a level set built from @a dense, a voxel where the field is far off
///          (outside any band it would be given) still counts: the reference alone decides where to look.
/// @param dense values on @a spec's voxels, x fastest; voxel (i,j,k) is the reference's index (i,j,k).
/// @param spec the dense grid; its voxel size is the unit of the error.
/// @note Reference voxels outside the dense grid count in onlyInB.
/// @throw Error when @a dense does not hold spec.voxelCount() values.
FieldError compareDenseWithReference(const std::vector<float>& dense, const GridSpec& spec,
                                     const openvdb::FloatGrid& reference);

} // namespace rtsdf
