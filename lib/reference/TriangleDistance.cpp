#include "reference/TriangleDistance.h"

namespace rtsdf {

glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                 TriangleFeature& feature) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) { feature = TriangleFeature::VertexA; return a; }

  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) { feature = TriangleFeature::VertexB; return b; }

  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    const float denom = d1 - d3;
    feature = TriangleFeature::EdgeAB;
    return denom > 0.0f ? a + (d1 / denom) * ab : a;
  }

  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) { feature = TriangleFeature::VertexC; return c; }

  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    const float denom = d2 - d6;
    feature = TriangleFeature::EdgeCA;
    return denom > 0.0f ? a + (d2 / denom) * ac : a;
  }

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

} // namespace rtsdf
