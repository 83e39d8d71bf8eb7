#include "reference/WindingRegions.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

namespace rtsdf {
namespace {

/// Neighbour lists reach this share of the mesh's largest extent: farther points use the winding number.
constexpr float kReachShare = 0.125f;
/// With more pieces than this (a triangle soup) or more neighbours than that, pieces are not told apart.
constexpr std::size_t kMaxPieces = 4096, kMaxNeighbours = 64;

/// Whether the fan of faces around @a v is one cycle (every edge at @a v has two faces running it opposite ways):
/// walking across the edges from one face must come back after visiting every face, else two fans meet at @a v.
bool oneFan(const WorldMesh& m, const VertexTriangles& around, unsigned v) {
  const unsigned n = around.count(v), first = around.triangles[around.start[v]];
  unsigned u = first, steps = 0;
  do {
    const glm::uvec3 t = m.triangles[u];
    const unsigned w = t[((t.x == v ? 0 : (t.y == v ? 1 : 2)) + 1) % 3]; // u runs the edge from v to w
    unsigned next = u;
    around.forEachAround(v, [&](unsigned o) {
      if (runs(m.triangles[o], w, v) > 0) next = o;
    });
    if (next == u) return false;
    u = next;
  } while (++steps < n && u != first);
  return steps == n && u == first;
}

} // namespace

MeshPieces connectedPieces(const WorldMesh& m, const VertexTriangles& around) {
  const std::size_t nt = m.triangles.size();
  std::vector<std::int64_t> across(3 * nt, -1); // per triangle, 3: the one other face on the edge, or -1
  std::vector<char> twoFaces(3 * nt, 0);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const unsigned a = tri[k], b = tri[(k + 1) % 3];
      int faces = 0;
      around.forEachAround(a, [&](unsigned u) {
        if (runs(m.triangles[u], a, b) == 0) return;
        ++faces;
        if (u != t) across[3 * t + k] = u;
      });
      twoFaces[3 * t + k] = faces == 2;
    }
  });
  std::vector<std::uint32_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (std::size_t e = 0; e < across.size(); ++e)
    if (twoFaces[e]) parent[root(std::uint32_t(e / 3))] = root(std::uint32_t(across[e]));
  MeshPieces out;
  out.pieceOf.resize(nt);
  std::vector<std::int64_t> index(nt, -1);
  for (std::uint32_t t = 0; t < nt; ++t) {
    std::int64_t& k = index[root(t)];
    if (k < 0) {
      k = std::int64_t(out.closed.size());
      out.closed.push_back(true);
    }
    out.pieceOf[t] = std::uint32_t(k);
    if (!twoFaces[3 * t] || !twoFaces[3 * t + 1] || !twoFaces[3 * t + 2]) out.closed[std::size_t(k)] = false;
  }
  return out;
}

WindingRegions::WindingRegions(const WorldMesh& mesh, const VertexTriangles& around, const MeshPieces& pieces)
    : mMesh(&mesh), mPieceOf(pieces.pieceOf) {
  findRim(mesh, around);
  findBoxes(mesh, pieces);
  Bounds bounds;
  for (const glm::vec3& p : mesh.positions) bounds.add(glm::dvec3(p));
  findNeighbours(kReachShare * float(bounds.maxExtent()));
}

void WindingRegions::findRim(const WorldMesh& m, const VertexTriangles& around) {
  const std::size_t nt = m.triangles.size();
  mRimEdge.assign(3 * nt, 0);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const unsigned a = tri[k], b = tri[(k + 1) % 3];
      int along = 0, against = 0; // faces on the edge that run it as this one does, and the other way
      around.forEachAround(a, [&](unsigned u) {
        const int r = runs(m.triangles[u], a, b);
        along += r > 0;
        against += r < 0;
      });
      mRimEdge[3 * t + k] = !(along == 1 && against == 1);
    }
  });
  mRimVertex.assign(m.positions.size(), 0);
  tbb::parallel_for(std::size_t(0), m.positions.size(), [&](std::size_t v) {
    bool rim = false;
    around.forEachAround(unsigned(v), [&](unsigned u) {
      const glm::uvec3 tri = m.triangles[u];
      const int k = tri.x == v ? 0 : (tri.y == v ? 1 : 2);
      rim = rim || mRimEdge[3 * u + k] || mRimEdge[3 * u + (k + 2) % 3];
    });
    mRimVertex[v] = rim || (around.count(unsigned(v)) > 0 && !oneFan(m, around, unsigned(v)));
  });
  mRimTriangle.resize(nt);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    mRimTriangle[t] = mRimEdge[3 * t] || mRimEdge[3 * t + 1] || mRimEdge[3 * t + 2] || mRimVertex[tri.x] ||
                      mRimVertex[tri.y] || mRimVertex[tri.z];
  });
}

void WindingRegions::findBoxes(const WorldMesh& m, const MeshPieces& pieces) {
  mLo.assign(pieces.count(), glm::vec3(INFINITY));
  mHi.assign(pieces.count(), glm::vec3(-INFINITY));
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t k = pieces.pieceOf[t];
      mLo[k] = glm::min(mLo[k], m.positions[m.triangles[t][c]]);
      mHi[k] = glm::max(mHi[k], m.positions[m.triangles[t][c]]);
    }
}

void WindingRegions::findNeighbours(float reach) {
  mReach = reach;
  const std::size_t n = mLo.size();
  mCrowded.assign(n, n > kMaxPieces);
  mNearStart.assign(n + 1, 0);
  if (n == 1 || n > kMaxPieces) return;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      // Per axis, a point within reach of both boxes has them at most 2 reach apart.
      const glm::vec3 gap = glm::max(mLo[b] - mHi[a], mLo[a] - mHi[b]);
      if (b != a && glm::all(glm::lessThanEqual(gap, glm::vec3(2.0f * reach)))) mNear.push_back(std::uint32_t(b));
    }
    mCrowded[a] = mNear.size() - mNearStart[a] > kMaxNeighbours;
    mNearStart[a + 1] = std::uint32_t(mNear.size());
  }
}

bool WindingRegions::onRim(unsigned triangle, TriangleFeature feature) const {
  const glm::uvec3 tri = mMesh->triangles[triangle];
  switch (feature) {
  case TriangleFeature::VertexA: return mRimVertex[tri.x] != 0;
  case TriangleFeature::VertexB: return mRimVertex[tri.y] != 0;
  case TriangleFeature::VertexC: return mRimVertex[tri.z] != 0;
  case TriangleFeature::EdgeAB: return mRimEdge[3 * triangle + 0] != 0;
  case TriangleFeature::EdgeBC: return mRimEdge[3 * triangle + 1] != 0;
  case TriangleFeature::EdgeCA: return mRimEdge[3 * triangle + 2] != 0;
  default: return false;
  }
}

bool WindingRegions::needed(const glm::vec3& p, float distance, unsigned triangle, TriangleFeature feature) const {
  if (onRim(triangle, feature)) return true;
  if (mLo.size() == 1) return false;
  const std::uint32_t piece = mPieceOf[triangle];
  if (mCrowded[piece] || !(distance <= mReach)) return true;
  for (std::uint32_t i = mNearStart[piece]; i < mNearStart[piece + 1]; ++i) {
    const std::uint32_t q = mNear[i];
    if (glm::all(glm::greaterThanEqual(p, mLo[q] - distance)) && glm::all(glm::lessThanEqual(p, mHi[q] + distance)))
      return true;
  }
  return false;
}

} // namespace rtsdf
