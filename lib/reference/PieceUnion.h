#pragma once
/// @file PieceUnion.h
/// @brief Closed pieces that pass through each other are a union: a point inside any of them is inside, whichever
///        surface is nearest to it (a character's limbs through its body, a table's legs through its top: what
///        OpenVDB's flood fill gives).
#include "scene/MeshRepair.h"
#include "scene/SceneGeometry.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace rtsdf {

class WindingNumberTree;

/// @brief The closed pieces of a scene's meshes whose boxes overlap another closed piece's box, each with a winding
///        tree of its own; the sign rules ask it about points the nearest surface says are outside.
class PieceUnion {
public:
  /// @brief The overlapping closed pieces among @a pieces, those of each mesh of @a geometry (meshPieces or
  ///        connectedPieces).
  /// @note @a geometry is referenced by the trees' triangles only while building: it need not outlive this object.
  PieceUnion(const SceneGeometry& geometry, std::vector<MeshPieces> pieces);
  ~PieceUnion();
  PieceUnion(const PieceUnion&) = delete;
  PieceUnion& operator=(const PieceUnion&) = delete;

  /// @brief Whether @a p lies inside a closed piece other than the one holding triangle @a triangle of mesh
  ///        @a mesh (the nearest surface): by the winding number of each overlapping piece whose box holds @a p.
  bool insideAnotherPiece(const glm::vec3& p, unsigned mesh, std::uint32_t triangle) const;

  /// @brief How many closed pieces overlap another's box (each costs a winding tree and, at points in its box
  ///        outside their nearest piece, an evaluation).
  std::size_t overlappingCount() const { return mOverlapping.size(); }

private:
  struct Piece {
    unsigned mesh = 0;
    std::uint32_t piece = 0;
    glm::vec3 lo{0.0f}, hi{0.0f};
    std::unique_ptr<WindingNumberTree> winding; // of the piece alone: 1 inside, 0 outside
  };
  std::vector<MeshPieces> mPieces; // per mesh
  std::vector<Piece> mOverlapping;
};

} // namespace rtsdf
