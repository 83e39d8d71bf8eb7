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

namespace detail {

/// Ericson's two regions next to corner B, and the same two next to corner C: the corner itself, then its edge from
/// A. own / other: dots of p - corner with the corner's edge from A and with the other edge from A; ownA: the dot of
/// p - a with the corner's edge; v: the barycentric weight that is zero on that edge.
/// @return whether p's closest point is there (then @a feature and @a closest are set).
inline bool nearCornerOrItsEdgeFromA(const glm::vec3& a, const glm::vec3& corner, const glm::vec3& edge, float ownA,
                                     float own, float other, float v, TriangleFeature cornerFeature,
                                     TriangleFeature edgeFeature, TriangleFeature& feature, glm::vec3& closest) {
  if (own >= 0.0f && other <= own) {
    feature = cornerFeature;
    closest = corner;
    return true;
  }
  if (v <= 0.0f && ownA >= 0.0f && own <= 0.0f) {
    const float denom = ownA - own;
    feature = edgeFeature;
    closest = denom > 0.0f ? a + (ownA / denom) * edge : a;
    return true;
  }
  return false;
}

} // namespace detail

/// @brief Closest point to @a p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
/// @param feature receives the feature the closest point lies on.
/// @return the closest point. Degenerate triangles give a point on their segment or vertex.
/// @note Inline: the exact band fill calls it hundreds of millions of times from tight loops.
inline glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                        const glm::vec3& c, TriangleFeature& feature) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) { feature = TriangleFeature::VertexA; return a; }

  glm::vec3 q;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  const float vc = d1 * d4 - d3 * d2;
  if (detail::nearCornerOrItsEdgeFromA(a, b, ab, d1, d3, d4, vc, TriangleFeature::VertexB, TriangleFeature::EdgeAB, feature, q))
    return q;

  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  const float vb = d5 * d2 - d1 * d6;
  if (detail::nearCornerOrItsEdgeFromA(a, c, ac, d2, d6, d5, vb, TriangleFeature::VertexC, TriangleFeature::EdgeCA, feature, q))
    return q;

  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    const float denom = (d4 - d3) + (d5 - d6);
    feature = TriangleFeature::EdgeBC;
    return denom > 0.0f ? b + ((d4 - d3) / denom) * (c - b) : b;
  }

  const float sum = va + vb + vc;
  if (!(sum > 0.0f)) {
    // Degenerate (zero-area) triangle: fall back to the nearest of its edges.
    feature = TriangleFeature::EdgeAB;
    auto onSegment = [&](const glm::vec3& s, const glm::vec3& e) {
      const glm::vec3 d = e - s;
      const float len2 = glm::dot(d, d);
      const float t = len2 > 0.0f ? glm::clamp(glm::dot(p - s, d) / len2, 0.0f, 1.0f) : 0.0f;
      return s + t * d;
    };
    const glm::vec3 q0 = onSegment(a, b), q1 = onSegment(b, c), q2 = onSegment(c, a);
    const float e0 = glm::dot(p - q0, p - q0), e1 = glm::dot(p - q1, p - q1), e2 = glm::dot(p - q2, p - q2);
    if (e1 < e0 && e1 <= e2) { feature = TriangleFeature::EdgeBC; return q1; }
    if (e2 < e0) { feature = TriangleFeature::EdgeCA; return q2; }
    return q0;
  }
  const float denom = 1.0f / sum;
  feature = TriangleFeature::Face;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// @brief Squared distance from @a p to triangle (a, b, c).
inline float distanceSquaredToTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                       const glm::vec3& c) {
  TriangleFeature f;
  const glm::vec3 d = p - closestPointOnTriangle(p, a, b, c, f);
  return glm::dot(d, d);
}

} // namespace rtsdf
