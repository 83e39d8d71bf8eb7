#pragma once
/// @file MeshRepair.h
/// @brief Orientation repair at load: a mesh's sign must not depend on the order of its faces' corners. Each
///        connected piece is oriented consistently (CGAL's orient_polygon_soup), keeping the orientation most of
///        its faces had, and each closed piece is turned outward (positive signed volume). Pieces that pass through
///        each other stay as they are: the sign rules treat closed pieces as a union (inside any is inside).
#include "scene/Mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief The connected pieces of a triangle list: triangles joined by an edge that exactly two triangles use.
struct MeshPieces {
  std::vector<std::uint32_t> pieceOf; ///< per triangle: its piece, 0 .. closed.size() - 1
  std::vector<bool> closed;           ///< per piece: every edge of its triangles is used by exactly two of them
  std::size_t count() const { return closed.size(); }
};

/// @brief The pieces of @a triangles (indices into a welded vertex list: validateMesh's output).
MeshPieces meshPieces(const std::vector<glm::uvec3>& triangles);

/// @brief Per piece, six times the signed volume its triangles enclose (positive when a closed piece faces
///        outward), in double.
std::vector<double> pieceSignedVolumes6(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::uvec3>& triangles, const MeshPieces& pieces);

/// @brief Orient @a mesh by solid, not by face order: consistently per connected piece (the orientation of most
///        of its faces kept), every closed piece facing outward. The positions and the triangles' order are
///        kept; only corner orders change. @a mesh must be welded (validateMesh does both).
OrientationRepair repairOrientation(Mesh& mesh);

} // namespace rtsdf
