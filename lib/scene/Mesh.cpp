#include "scene/Mesh.h"

#include "scene/MeshRepair.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <unordered_map>

namespace rtsdf {
namespace {

std::string where(const Mesh& m) {
  return m.source == m.name || m.name.empty() ? m.source : fmt::format("{} (object '{}')", m.source, m.name);
}

struct PositionHash {
  std::size_t operator()(const glm::vec3& p) const {
    std::uint32_t b[3];
    static_assert(sizeof(b) == sizeof(glm::vec3));
    std::memcpy(b, &p, sizeof(b));
    std::size_t h = b[0];
    h = h * 0x9E3779B97F4A7C15ull ^ b[1];
    h = h * 0x9E3779B97F4A7C15ull ^ b[2];
    return h;
  }
};

} // namespace

Bounds positionBounds(const Mesh& mesh) {
  Bounds b;
  for (const glm::vec3& p : mesh.positions) b.add(glm::dvec3(p));
  return b;
}

bool hasFloatArea(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float n2 = glm::dot(n, n);
  return n2 >= std::numeric_limits<float>::min() && std::isfinite(n2);
}

MeshReport validateMesh(Mesh& mesh) {
  MeshReport r;
  r.inputTriangles = mesh.triangles.size();
  r.inputVertices = mesh.positions.size();
  if (mesh.triangles.empty())
    throw Error(fmt::format("{}: empty mesh (no triangles)", where(mesh)));

  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3& p = mesh.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(fmt::format("{}: vertex {} has a non-finite coordinate ({}, {}, {})", where(mesh), v, p.x, p.y,
                              p.z));
    const float m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (m > kMaxCoordinate)
      throw Error(fmt::format("{}: vertex {} has the coordinate {:g}, beyond the ±{:g} rtsdf supports (float "
                              "precision): scale the model down", where(mesh), v, m, kMaxCoordinate));
  }
  const std::size_t nv = mesh.positions.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c)
      if (tri[c] >= nv)
        throw Error(fmt::format("{}: triangle {} uses vertex index {} but the mesh has {} vertices", where(mesh),
                                t, tri[c], nv));
  }

  // Weld vertices with identical positions so that topology (closed or open) is seen across split normals/UVs.
  std::unordered_map<glm::vec3, std::uint32_t, PositionHash> first;
  first.reserve(nv);
  std::vector<std::uint32_t> remap(nv);
  std::vector<glm::vec3> welded;
  welded.reserve(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    auto [it, inserted] = first.emplace(mesh.positions[v], std::uint32_t(welded.size()));
    if (inserted) welded.push_back(mesh.positions[v]);
    remap[v] = it->second;
  }
  r.weldedVertices = nv - welded.size();

  std::vector<glm::uvec3> kept;
  kept.reserve(mesh.triangles.size());
  for (const glm::uvec3& t0 : mesh.triangles) {
    const glm::uvec3 t(remap[t0.x], remap[t0.y], remap[t0.z]);
    if (t.x == t.y || t.y == t.z || t.x == t.z) { ++r.degenerateDropped; continue; }
    if (!hasFloatArea(welded[t.x], welded[t.y], welded[t.z])) { ++r.degenerateDropped; continue; }
    kept.push_back(t);
  }
  if (kept.empty())
    throw Error(fmt::format("{}: empty mesh: all {} triangles have zero area", where(mesh), r.inputTriangles));

  // Drop vertices no kept triangle uses.
  std::vector<std::uint32_t> used(welded.size(), UINT32_MAX);
  std::vector<glm::vec3> positions;
  for (glm::uvec3& t : kept)
    for (int c = 0; c < 3; ++c) {
      if (used[t[c]] == UINT32_MAX) { used[t[c]] = std::uint32_t(positions.size()); positions.push_back(welded[t[c]]); }
      t[c] = used[t[c]];
    }
  mesh.positions = std::move(positions);
  mesh.triangles = std::move(kept);
  r.triangles = mesh.triangles.size();
  // The sign follows the solid, not the order of the corners (inside-out exports, faces flipped at random).
  r.orientation = repairOrientation(mesh);
  analyzeTopology(mesh, r);
  return r;
}

void analyzeTopology(const Mesh& mesh, MeshReport& r) {
  // Directed half-edges keyed by (min, max); count uses and the direction balance.
  struct EdgeUse { std::uint32_t count = 0; std::int32_t forward = 0; };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (const glm::uvec3& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = t[c], b = t[(c + 1) % 3];
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      EdgeUse& e = edges[key];
      ++e.count;
      e.forward += a < b ? 1 : -1;
    }
  r.boundaryEdges = r.nonManifoldEdges = r.misorientedEdges = 0;
  for (const auto& [key, e] : edges) {
    if (e.count == 1) ++r.boundaryEdges;
    else if (e.count > 2) ++r.nonManifoldEdges;
    else if (e.forward != 0) ++r.misorientedEdges;
  }
}

Mesh makeBoxMesh(const glm::vec3& size, std::string name) {
  if (!(size.x > 0 && size.y > 0 && size.z > 0) || !std::isfinite(size.x + size.y + size.z))
    throw Error(fmt::format("box '{}': size ({}, {}, {}) must be positive and finite", name, size.x, size.y, size.z));
  Mesh m;
  m.name = std::move(name);
  m.source = "<box>";
  const glm::vec3 h = 0.5f * size;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
  // Faces as quads (counter-clockwise from outside), split into two triangles each.
  const unsigned quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

namespace {

/// Split every triangle of (v, f) in four at its edge points midpointOf(a, b), one new vertex per edge.
template <class Midpoint>
void splitInFour(std::vector<glm::dvec3>& v, std::vector<glm::uvec3>& f, Midpoint midpointOf) {
  std::unordered_map<std::uint64_t, unsigned> mid;
  mid.reserve(f.size() * 2);
  auto midpoint = [&](unsigned a, unsigned b) {
    const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    const auto [it, inserted] = mid.emplace(key, unsigned(v.size()));
    if (inserted) v.push_back(midpointOf(v[a], v[b]));
    return it->second;
  };
  std::vector<glm::uvec3> g;
  g.reserve(4 * f.size());
  for (const glm::uvec3& tri : f) {
    const unsigned ab = midpoint(tri.x, tri.y), bc = midpoint(tri.y, tri.z), ca = midpoint(tri.z, tri.x);
    g.insert(g.end(), {{tri.x, ab, ca}, {tri.y, bc, ab}, {tri.z, ca, bc}, {ab, bc, ca}});
  }
  f.swap(g);
}

} // namespace

Mesh subdivideMesh(const Mesh& mesh, int levels) {
  if (levels < 0 || levels > 6)
    throw Error(fmt::format("mesh '{}': subdivision levels {} must be in [0, 6]", mesh.name, levels));
  std::vector<glm::dvec3> v(mesh.positions.begin(), mesh.positions.end());
  std::vector<glm::uvec3> f = mesh.triangles;
  for (int l = 0; l < levels; ++l)
    splitInFour(v, f, [](const glm::dvec3& a, const glm::dvec3& b) { return 0.5 * (a + b); });
  Mesh m{mesh.name, mesh.source, {}, std::move(f)};
  m.positions.reserve(v.size());
  for (const glm::dvec3& p : v) m.positions.push_back(glm::vec3(p));
  return m;
}

Mesh cutHoles(const Mesh& mesh, int holes, float radius) {
  Mesh m{mesh.name, mesh.source, mesh.positions, {}};
  if (holes < 1 || mesh.positions.empty()) { m.triangles = mesh.triangles; return m; }
  std::vector<glm::vec3> centres;
  for (int h = 0; h < holes; ++h) centres.push_back(mesh.positions[(2 * h + 1) * mesh.positions.size() / (2 * holes)]);
  auto nearAHole = [&](unsigned v) {
    for (const glm::vec3& c : centres)
      if (glm::distance(mesh.positions[v], c) < radius) return true;
    return false;
  };
  for (const glm::uvec3& t : mesh.triangles)
    if (!nearAHole(t.x) && !nearAHole(t.y) && !nearAHole(t.z)) m.triangles.push_back(t);
  return m;
}

Mesh makeTorusMesh(float R, float r, int rings, int sides, std::string name) {
  Mesh m;
  m.name = std::move(name);
  m.source = "<torus>";
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const float u = 2.0f * glm::pi<float>() * i / rings, v = 2.0f * glm::pi<float>() * j / sides;
      m.positions.emplace_back((R + r * std::cos(v)) * std::cos(u), r * std::sin(v), (R + r * std::cos(v)) * std::sin(u));
    }
  auto id = [&](int i, int j) { return unsigned(((i + rings) % rings) * sides + (j + sides) % sides); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.triangles.emplace_back(a, c, b);
      m.triangles.emplace_back(a, d, c);
    }
  return m;
}

Mesh makeSphereMesh(float radius, int subdivisions, std::string name) {
  if (!(radius > 0.0f) || !std::isfinite(radius))
    throw Error(fmt::format("sphere '{}': radius {} must be positive and finite", name, radius));
  if (subdivisions < 0 || subdivisions > 7)
    throw Error(fmt::format("sphere '{}': subdivisions {} must be in [0, 7]", name, subdivisions));
  Mesh m;
  m.name = std::move(name);
  m.source = "<sphere>";
  // Work in double on the unit sphere, round once at the end.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                               {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s)
    splitInFour(v, f, [](const glm::dvec3& a, const glm::dvec3& b) { return glm::normalize(a + b); });
  m.positions.reserve(v.size());
  for (const glm::dvec3& p : v) m.positions.push_back(glm::vec3(p * double(radius)));
  m.triangles = std::move(f);
  return m;
}

} // namespace rtsdf
