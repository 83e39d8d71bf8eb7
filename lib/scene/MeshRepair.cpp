#include "scene/MeshRepair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>

#include <array>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace rtsdf {
namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

/// Union-find over triangles.
struct Pieces {
  std::vector<std::uint32_t> parent;
  explicit Pieces(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  }
  void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

/// Records which polygons orient_polygon_soup reversed (it may reverse one more than once). The visitor is copied
/// into the call: it writes through a pointer.
struct ReversalVisitor : CGAL::Polygon_mesh_processing::Default_orientation_visitor {
  std::vector<bool>* reversed = nullptr;
  void polygon_orientation_reversed(std::size_t p) { (*reversed)[p] = !(*reversed)[p]; }
};

/// Per triangle: whether CGAL's consistent orientation reverses it.
std::vector<bool> consistentOrientationFlips(const Mesh& mesh) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  std::vector<Point> points;
  points.reserve(mesh.positions.size());
  for (const glm::vec3& p : mesh.positions) points.emplace_back(p.x, p.y, p.z);
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const glm::uvec3& t : mesh.triangles) polygons.push_back({t.x, t.y, t.z});
  std::vector<bool> reversed(mesh.triangles.size(), false);
  ReversalVisitor visitor;
  visitor.reversed = &reversed;
  // Vertices CGAL duplicates at non-manifold points are its own: only the reversals are applied to the mesh.
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons,
                                                     CGAL::parameters::visitor(visitor));
  return reversed;
}

} // namespace

MeshPieces meshPieces(const std::vector<glm::uvec3>& triangles) {
  struct EdgeUse { std::uint32_t first = 0, second = 0, count = 0; };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(triangles.size() * 2);
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      EdgeUse& e = edges[edgeKey(triangles[t][c], triangles[t][(c + 1) % 3])];
      (e.count == 0 ? e.first : e.second) = t;
      ++e.count;
    }
  // Only edges exactly two triangles share join pieces: a non-manifold edge is where pieces meet, not a seam.
  Pieces uf(triangles.size());
  for (const auto& [key, e] : edges)
    if (e.count == 2) uf.join(e.first, e.second);
  MeshPieces out;
  out.pieceOf.assign(triangles.size(), 0);
  std::unordered_map<std::uint32_t, std::uint32_t> index;
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    const auto [it, inserted] = index.emplace(uf.find(t), std::uint32_t(out.closed.size()));
    if (inserted) out.closed.push_back(true);
    out.pieceOf[t] = it->second;
  }
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      if (edges[edgeKey(triangles[t][c], triangles[t][(c + 1) % 3])].count != 2) out.closed[out.pieceOf[t]] = false;
  return out;
}

std::vector<double> pieceSignedVolumes6(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::uvec3>& triangles, const MeshPieces& pieces) {
  std::vector<double> v(pieces.count(), 0.0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::dvec3 a(positions[triangles[t].x]), b(positions[triangles[t].y]), c(positions[triangles[t].z]);
    v[pieces.pieceOf[t]] += glm::dot(a, glm::cross(b, c));
  }
  return v;
}

OrientationRepair repairOrientation(Mesh& mesh) {
  OrientationRepair r;
  std::vector<bool> flip = consistentOrientationFlips(mesh);
  const MeshPieces pieces = meshPieces(mesh.triangles);
  r.pieces = pieces.count();
  // Keep the orientation most of a piece's triangles had: reverse the whole piece where CGAL reversed the majority.
  std::vector<std::size_t> size(pieces.count(), 0), flipped(pieces.count(), 0);
  for (std::size_t t = 0; t < flip.size(); ++t) {
    ++size[pieces.pieceOf[t]];
    flipped[pieces.pieceOf[t]] += flip[t] ? 1 : 0;
  }
  for (std::size_t t = 0; t < flip.size(); ++t)
    if (2 * flipped[pieces.pieceOf[t]] > size[pieces.pieceOf[t]]) flip[t] = !flip[t];
  for (std::size_t t = 0; t < flip.size(); ++t)
    if (flip[t]) std::swap(mesh.triangles[t].y, mesh.triangles[t].z);
  // Closed pieces bound a volume: turn those that face inward.
  const std::vector<double> volume = pieceSignedVolumes6(mesh.positions, mesh.triangles, pieces);
  std::vector<bool> turn(pieces.count(), false);
  for (std::uint32_t p = 0; p < pieces.count(); ++p) {
    if (!pieces.closed[p]) continue;
    ++r.closedPieces;
    turn[p] = volume[p] < 0.0;
    r.piecesTurnedOutward += turn[p] ? 1 : 0;
  }
  for (std::size_t t = 0; t < flip.size(); ++t)
    if (turn[pieces.pieceOf[t]]) {
      std::swap(mesh.triangles[t].y, mesh.triangles[t].z);
      flip[t] = !flip[t];
    }
  for (bool f : flip) r.reorientedTriangles += f ? 1 : 0;
  return r;
}

} // namespace rtsdf
