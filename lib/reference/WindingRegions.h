#pragma once
/// @file WindingRegions.h
/// @brief Where an open mesh's sign needs its winding number, point by point. Off the rim of a piece (its boundary,
///        non-manifold and mis-oriented edges, and pinched vertices) the pseudo-normal gives the side of the nearest
///        surface exactly; it gives the winding number's side too unless another piece can shift that number by a
///        half: one that encloses the point or comes as near to it as its nearest surface. Both need the point
///        within its distance of that piece's bounding box, which is what is tested.
#include "reference/TriangleDistance.h"
#include "reference/VertexTriangles.h"
#include "scene/MeshRepair.h"
#include "scene/SceneGeometry.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace rtsdf {

/// @brief The pieces of @a mesh as meshPieces defines them (triangles joined by edges of exactly two faces; a piece
///        is closed when every edge of it has two), found through the triangles around each vertex in parallel.
MeshPieces connectedPieces(const WorldMesh& mesh, const VertexTriangles& around);

/// @brief The rim and the pieces of one open mesh, and per piece the other pieces whose boxes lie near its own.
class WindingRegions {
public:
  /// @param around the triangles around each vertex of @a mesh; @param pieces its connectedPieces.
  WindingRegions(const WorldMesh& mesh, const VertexTriangles& around, const MeshPieces& pieces);

  /// @brief Whether the winding number must sign a point @a p at @a distance from the mesh whose closest feature is
  ///        @a feature of @a triangle: the feature touches the rim, or @a p lies within @a distance of the box of a
  ///        piece other than the triangle's (or farther than the neighbour lists reach, or by a piece with too many
  ///        neighbours to test).
  bool needed(const glm::vec3& p, float distance, unsigned triangle, TriangleFeature feature) const;

  std::size_t pieceCount() const { return mLo.size(); }
  std::uint32_t pieceOf(unsigned triangle) const { return mPieceOf[triangle]; }
  /// @brief Whether an edge or a corner of @a triangle is on the rim.
  bool touchesRim(unsigned triangle) const { return mRimTriangle[triangle] != 0; }
  /// @brief Whether @a feature of @a triangle (an edge or a corner; a face never) is on the rim.
  bool onRim(unsigned triangle, TriangleFeature feature) const;

private:
  void findRim(const WorldMesh& mesh, const VertexTriangles& around);
  void findBoxes(const WorldMesh& mesh, const MeshPieces& pieces);
  void findNeighbours(float reach);

  const WorldMesh* mMesh;
  std::vector<char> mRimEdge;   ///< per triangle, 3 (AB, BC, CA): not exactly two faces running it opposite ways
  std::vector<char> mRimVertex; ///< per vertex: on a rim edge, or where two fans of faces meet
  std::vector<char> mRimTriangle; ///< per triangle: an edge or a corner on the rim
  std::vector<std::uint32_t> mPieceOf;        ///< per triangle
  std::vector<glm::vec3> mLo, mHi;            ///< per piece: its box
  std::vector<std::uint32_t> mNearStart, mNear; ///< per piece: other pieces whose boxes lie within 2 mReach
  std::vector<char> mCrowded;                 ///< per piece: too many neighbours to test: winding number throughout
  float mReach = 0.0f;                        ///< distances up to which the neighbour lists are complete
};

} // namespace rtsdf
