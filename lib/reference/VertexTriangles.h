#pragma once
/// @file VertexTriangles.h
/// @brief The triangles around each vertex of an indexed mesh, and how a triangle runs an edge: the adjacency the
///        exact field's pseudo-normals and sign regions are built from (no hash map of edges).
#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace rtsdf {

/// @brief The triangles around each vertex: those of vertex v are triangles[start[v] .. start[v + 1]) (a triangle
///        that repeats a vertex is listed once per corner).
struct VertexTriangles {
  std::vector<unsigned> start, triangles;
  VertexTriangles(std::size_t vertices, const std::vector<glm::uvec3>& tris) : start(vertices + 1, 0u) {
    for (const glm::uvec3& t : tris)
      for (int k = 0; k < 3; ++k) ++start[t[k] + 1];
    for (std::size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
    triangles.resize(start.back());
    std::vector<unsigned> next(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (int k = 0; k < 3; ++k) triangles[next[tris[t][k]]++] = unsigned(t);
  }
  unsigned count(unsigned v) const { return start[v + 1] - start[v]; }
  template <class F> void forEachAround(unsigned v, F&& f) const {
    for (unsigned i = start[v]; i < start[v + 1]; ++i) f(triangles[i]);
  }
};

/// @brief How triangle @a u runs the edge between @a a and @a b: +1 from a to b, -1 from b to a, 0 not at all.
inline int runs(const glm::uvec3& u, unsigned a, unsigned b) {
  for (int j = 0; j < 3; ++j) {
    if (u[j] == a && u[(j + 1) % 3] == b) return 1;
    if (u[j] == b && u[(j + 1) % 3] == a) return -1;
  }
  return 0;
}

} // namespace rtsdf
