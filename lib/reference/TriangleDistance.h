#pragma once
/// @file TriangleDistance.h
/// @brief Closest point on a triangle with the feature it lies on (face, edge or vertex), the basis of the
///        exact distance and of the angle-weighted pseudo-normal sign.
#include <glm/glm.hpp>

namespace rtsdf {

/// @brief The part of a triangle (a, b, c) a closest point lies on.
enum class TriangleFeature : int {
  Face = 0,
  VertexA = 1, VertexB = 2, VertexC = 3,
  EdgeAB = 4, EdgeBC = 5, EdgeCA = 6
};

/// @brief Closest point to @a p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
/// @param feature receives the feature the closest point lies on.
/// @return the closest point. Degenerate triangles give a point on their segment or vertex.
glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                 TriangleFeature& feature);

/// @brief Squared distance from @a p to triangle (a, b, c).
inline float distanceSquaredToTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                       const glm::vec3& c) {
  TriangleFeature f;
  const glm::vec3 d = p - closestPointOnTriangle(p, a, b, c, f);
  return glm::dot(d, d);
}

} // namespace rtsdf
