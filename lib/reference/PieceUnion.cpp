#include "reference/PieceUnion.h"

#include "reference/WindingNumber.h"

#include <cmath>

namespace rtsdf {

PieceUnion::PieceUnion(const SceneGeometry& geometry, std::vector<MeshPieces> pieces) : mPieces(std::move(pieces)) {
  std::vector<Piece> closed;
  for (unsigned m = 0; m < geometry.meshes.size(); ++m) {
    const WorldMesh& wm = geometry.meshes[m];
    const MeshPieces& pieces = mPieces[m];
    std::vector<std::int64_t> slot(pieces.count(), -1);
    for (std::uint32_t p = 0; p < pieces.count(); ++p)
      if (pieces.closed[p]) {
        slot[p] = std::int64_t(closed.size());
        closed.push_back({m, p, glm::vec3(INFINITY), glm::vec3(-INFINITY), nullptr});
      }
    for (std::size_t t = 0; t < wm.triangles.size(); ++t) {
      const std::int64_t k = slot[pieces.pieceOf[t]];
      if (k < 0) continue;
      Piece& c = closed[std::size_t(k)];
      for (int corner = 0; corner < 3; ++corner) {
        c.lo = glm::min(c.lo, wm.positions[wm.triangles[t][corner]]);
        c.hi = glm::max(c.hi, wm.positions[wm.triangles[t][corner]]);
      }
    }
  }
  // Pieces whose boxes are apart cannot hold each other's points: only the others need a tree.
  std::vector<bool> overlaps(closed.size(), false);
  for (std::size_t a = 0; a < closed.size(); ++a)
    for (std::size_t b = a + 1; b < closed.size(); ++b)
      if (glm::all(glm::lessThanEqual(closed[a].lo, closed[b].hi)) &&
          glm::all(glm::lessThanEqual(closed[b].lo, closed[a].hi)))
        overlaps[a] = overlaps[b] = true;
  for (std::size_t k = 0; k < closed.size(); ++k) {
    if (!overlaps[k]) continue;
    Piece& o = closed[k];
    const WorldMesh& wm = geometry.meshes[o.mesh];
    std::vector<glm::uvec3> tris;
    for (std::size_t t = 0; t < wm.triangles.size(); ++t)
      if (mPieces[o.mesh].pieceOf[t] == o.piece) tris.push_back(wm.triangles[t]);
    o.winding = std::make_unique<WindingNumberTree>(wm.positions, tris);
    mOverlapping.push_back(std::move(o));
  }
}

PieceUnion::~PieceUnion() = default;

bool PieceUnion::insideAnotherPiece(const glm::vec3& p, unsigned mesh, std::uint32_t triangle) const {
  if (mOverlapping.empty()) return false; // the common case, on every outside voxel of a bake
  const std::uint32_t nearest = mPieces[mesh].pieceOf[triangle];
  for (const Piece& o : mOverlapping) {
    if ((o.mesh == mesh && o.piece == nearest) || glm::any(glm::lessThan(p, o.lo)) ||
        glm::any(glm::greaterThan(p, o.hi)))
      continue;
    if (o.winding->inside(glm::dvec3(p))) return true;
  }
  return false;
}

} // namespace rtsdf
