#include "reference/TriangleDistance.h"
#include "reference/WindingNumber.h"
#include "TestUtil.h"

#include <gtest/gtest.h>

#include <random>

using namespace rtsdf;

TEST(TriangleDistance, FeaturesOfTheClosestPoint) {
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  TriangleFeature f;
  glm::vec3 q = closestPointOnTriangle({0.2f, 0.2f, 1.0f}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::Face);
  EXPECT_NEAR(glm::length(q - glm::vec3(0.2f, 0.2f, 0)), 0.0f, 1e-6f);
  closestPointOnTriangle({-1, -1, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::VertexA);
  closestPointOnTriangle({2, -0.5f, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::VertexB);
  closestPointOnTriangle({-0.5f, 2, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::VertexC);
  q = closestPointOnTriangle({0.5f, -1, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::EdgeAB);
  EXPECT_NEAR(q.x, 0.5f, 1e-6f);
  closestPointOnTriangle({1, 1, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::EdgeBC);
  closestPointOnTriangle({-1, 0.5f, 0}, a, b, c, f);
  EXPECT_EQ(f, TriangleFeature::EdgeCA);
}

TEST(TriangleDistance, MatchesDenseSamplingOfTheTriangle) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const glm::vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    const float d = std::sqrt(distanceSquaredToTriangle(p, a, b, c));
    float best = INFINITY;
    const int n = 200;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const glm::vec3 s = a + (b - a) * (float(i) / n) + (c - a) * (float(j) / n);
        best = std::min(best, glm::length(p - s));
      }
    // Sampling over-estimates by at most half the sample spacing.
    const float spacing = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)}) / n;
    EXPECT_LE(d, best + 1e-5f);
    EXPECT_GE(d, best - spacing);
  }
}

TEST(TriangleDistance, DegenerateTrianglesGiveSegmentDistance) {
  TriangleFeature f;
  const glm::vec3 q = closestPointOnTriangle({0.5f, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, f);
  EXPECT_NEAR(glm::length(q - glm::vec3(0.5f, 0, 0)), 0.0f, 1e-6f);
}

TEST(WindingNumber, InsideOneOutsideZeroAndTreeMatchesExactSum) {
  const Mesh sphere = test::makeSphere(0.5f, 4);
  const WindingNumberTree tree(sphere.positions, sphere.triangles);
  EXPECT_NEAR(tree.evaluateExact({0, 0, 0}), 1.0, 1e-9);
  EXPECT_NEAR(tree.evaluateExact({2, 0, 0}), 0.0, 1e-9);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    if (std::fabs(glm::length(p) - 0.5) < 0.02) continue; // the surface itself
    const double exact = tree.evaluateExact(p);
    EXPECT_NEAR(exact, glm::length(p) < 0.5 ? 1.0 : 0.0, 1e-6);
    EXPECT_NEAR(tree.evaluate(p), exact, 0.05); // dipole far field: a few 1e-2 near the surface
  }
}

TEST(WindingNumber, OpenHemisphereIsHalfAtItsCentre) {
  // Keep only the upper half of a sphere: at the centre it subtends half the full solid angle.
  const Mesh sphere = test::makeSphere(1.0f, 4);
  std::vector<glm::uvec3> upper;
  for (const auto& t : sphere.triangles)
    if (sphere.positions[t.x].y + sphere.positions[t.y].y + sphere.positions[t.z].y > 0.0f) upper.push_back(t);
  const WindingNumberTree tree(sphere.positions, upper);
  EXPECT_NEAR(tree.evaluateExact({0, 0, 0}), 0.5, 0.02);
  EXPECT_NEAR(tree.evaluate({0, 0, 0}), tree.evaluateExact({0, 0, 0}), 0.05);
  EXPECT_GT(tree.evaluate({0, 0.9, 0}), 0.5);  // under the dome
  EXPECT_LT(tree.evaluate({0, -0.9, 0}), 0.5); // below the opening
}
