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

/// @brief Error statistics of a field against a reference, in voxels of the field's grid.
struct FieldError {
  std::uint64_t voxels = 0;        ///< voxels compared (active in both)
  double meanAbs = 0.0;            ///< mean |a - b| / voxel size
  double rms = 0.0;                ///< sqrt(mean (a - b)^2) / voxel size
  double maxAbs = 0.0;             ///< max |a - b| / voxel size
  std::uint64_t signMismatches = 0;///< voxels where exactly one of a, b is negative, neither on the surface
  std::uint64_t onlyInA = 0;       ///< active in A only
  std::uint64_t onlyInB = 0;       ///< active in B only
  double signErrorRate() const { return voxels ? double(signMismatches) / double(voxels) : 0.0; }
  std::string summary() const;
};

/// @brief Compare two grids voxel by voxel over the voxels active in both.
/// @throw Error when the grids' transforms differ (they must share voxel size and offset).
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
