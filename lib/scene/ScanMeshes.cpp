#include "scene/ScanMeshes.h"

#include "util/Error.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace rtsdf {
namespace {

glm::vec3 centroid(const Mesh& m, const glm::uvec3& t) {
  return (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f;
}

glm::vec3 faceNormal(const Mesh& m, const glm::uvec3& t) {
  return glm::normalize(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
}

/// Per vertex: the normalized sum of its triangles' unit normals.
std::vector<glm::vec3> vertexNormals(const Mesh& m) {
  std::vector<glm::vec3> n(m.positions.size(), glm::vec3(0.0f));
  for (const glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) n[t[k]] += faceNormal(m, t);
  for (glm::vec3& v : n) v = glm::length(v) > 0.0f ? glm::normalize(v) : glm::vec3(0.0f, 1.0f, 0.0f);
  return n;
}

/// The first triangle from the middle of @a m's list on whose edge (a, b) exactly two triangles lie.
glm::uvec3 interiorTriangle(const Mesh& m) {
  std::unordered_map<std::uint64_t, int> uses;
  auto key = [](unsigned a, unsigned b) { return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
  for (const glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++uses[key(t[k], t[(k + 1) % 3])];
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const glm::uvec3 t = m.triangles[(m.triangles.size() / 2 + i) % m.triangles.size()];
    if (uses[key(t.x, t.y)] == 2) return t;
  }
  return m.triangles.front();
}

/// A hexagonal disc of radius @a r at @a centre facing @a normal, appended to @a m.
void addDisc(Mesh& m, const glm::vec3& centre, const glm::vec3& normal, float r) {
  const glm::vec3 u = glm::normalize(glm::cross(normal, std::fabs(normal.x) < 0.9f ? glm::vec3(1, 0, 0)
                                                                                     : glm::vec3(0, 1, 0)));
  const glm::vec3 v = glm::cross(normal, u);
  const unsigned base = unsigned(m.positions.size());
  m.positions.push_back(centre);
  for (int k = 0; k < 6; ++k) {
    const float a = glm::two_pi<float>() * float(k) / 6.0f;
    m.positions.push_back(centre + r * (std::cos(a) * u + std::sin(a) * v));
  }
  for (unsigned k = 0; k < 6; ++k) m.triangles.emplace_back(base, base + 1 + k, base + 1 + (k + 1) % 6);
}

} // namespace

Mesh makeSphereInPatches(int subdivisions, float gap) {
  const Mesh sphere = makeSphereMesh(1.0f, subdivisions, "sphere in patches");
  Mesh m{sphere.name, "<sphere in patches>", sphere.positions, {}};
  for (const glm::uvec3& t : sphere.triangles) {
    const glm::vec3 c = glm::abs(centroid(sphere, t));
    if (std::min({c.x, c.y, c.z}) >= gap) m.triangles.push_back(t);
  }
  return m;
}

Mesh makeScanInPieces(const Mesh& closed, int holes) {
  if (closed.triangles.empty()) throw Error("makeScanInPieces: the mesh has no triangles");
  const Bounds bounds = positionBounds(closed);
  const float extent = float(bounds.maxExtent()), middle = float(bounds.center().y);
  const std::vector<glm::vec3> normals = vertexNormals(closed);
  const Mesh holed = cutHoles(closed, holes, 0.03f * extent);
  Mesh m{closed.name, "<scan in pieces>", closed.positions, {}};
  for (const glm::uvec3& t : holed.triangles)
    if (std::fabs(centroid(holed, t).y - middle) >= 0.01f * extent) m.triangles.push_back(t);
  // A fin on an interior edge (a, b): the edge then has three faces.
  const glm::uvec3 base = interiorTriangle(m);
  const glm::vec3 mid = 0.5f * (m.positions[base.x] + m.positions[base.y]);
  m.positions.push_back(mid + 0.03f * extent * faceNormal(m, base));
  m.triangles.emplace_back(base.x, base.y, unsigned(m.positions.size() - 1));
  for (int k = 0; k < 6; ++k) {
    const std::size_t v = (2 * std::size_t(k) + 1) * closed.positions.size() / 12;
    const float side = k % 2 == 0 ? 1.0f : -1.0f;
    addDisc(m, closed.positions[v] + side * 0.02f * extent * normals[v], normals[v], 0.01f * extent);
  }
  return m;
}

} // namespace rtsdf
