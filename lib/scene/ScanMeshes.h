#pragma once
/// @file ScanMeshes.h
/// @brief Open scans of several pieces, generated reproducibly for the exact field's tests and benchmarks: a sphere
///        cut into separated patches, and a scan in pieces with a non-manifold fin and floating fragments.
#include "scene/Mesh.h"

namespace rtsdf {

/// @brief The unit icosphere (@a subdivisions as in makeSphereMesh) cut by the three coordinate planes into eight open
///        patches with gaps between them: the triangles whose centroid lies within @a gap of a plane are dropped.
/// @note Away from the gaps its winding number is the ball's (about 1 inside, 0 outside).
Mesh makeSphereInPatches(int subdivisions, float gap);

/// @brief A scan in pieces made from the closed, outward-facing @a closed: @a holes holes cut (radius 3% of its
///        extent E, cutHoles), split in two by the plane through its centre across y (triangles whose centroid is
///        within 0.01 E of it dropped), one fin triangle standing on an interior edge (an edge of three faces), and
///        six small discs floating 0.02 E off the surface, alternately outside and inside (scan noise).
/// @throw Error when @a closed has no triangles.
Mesh makeScanInPieces(const Mesh& closed, int holes);

} // namespace rtsdf
