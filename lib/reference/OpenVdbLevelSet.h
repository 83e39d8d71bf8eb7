#pragma once
/// @file OpenVdbLevelSet.h
/// @brief OpenVDB's own narrow-band level set (tools::meshToLevelSet): the second reference, behind the same
///        interface as the exact SDF (scene geometry and a GridSpec in, a level set on the same voxels out).
#include "grid/GridSpec.h"
#include "scene/SceneGeometry.h"

#include <openvdb/openvdb.h>

namespace rtsdf {

/// @brief OpenVDB's meshToLevelSet of all scene triangles on the voxels of @a spec.
/// @param band half-width in world units (converted to voxels for OpenVDB; at least 1 voxel).
/// @note OpenVDB computes exact distances next to the surface and propagates nearest-triangle indices
///       outward, and signs by flood fill: inside means enclosed. It bounds the result to the grid's box.
openvdb::FloatGrid::Ptr openvdbLevelSet(const SceneGeometry& geometry, const GridSpec& spec, double band);

/// @brief OpenVDB's full-domain signed distance field (meshToSignedDistanceField) over the whole grid.
openvdb::FloatGrid::Ptr openvdbSignedDistanceField(const SceneGeometry& geometry, const GridSpec& spec);

} // namespace rtsdf
