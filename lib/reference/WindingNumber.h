#pragma once
/// @file WindingNumber.h
/// @brief Generalized winding number of a triangle mesh (Jacobson et al. 2013), evaluated with the
///        hierarchical dipole approximation of Barill et al. 2018 ("fast winding numbers").
#include <glm/glm.hpp>

#include <vector>

namespace rtsdf {

/// @brief w(p) = (1/4pi) * sum of the signed solid angles of the triangles seen from p: 1 inside a closed
///        outward-oriented mesh, 0 outside, and a smooth, robust inside/outside measure (w >= 1/2) for open,
///        self-intersecting or non-manifold meshes.
class WindingNumberTree {
public:
  /// @param positions vertices; @param triangles counter-clockwise seen from outside.
  /// @param beta accuracy: a cluster is replaced by its dipole when it is farther than beta * its radius.
  ///        With 2, errors stay below ~0.04 at points a few triangle sizes from the surface (tested): ample
  ///        for the sign test w >= 1/2; larger is slower and more exact.
  WindingNumberTree(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                    double beta = 2.0);

  /// @brief The winding number at @a p (approximate only through the far-field dipoles).
  double evaluate(const glm::dvec3& p) const { return evaluate(p, mBeta); }
  /// @brief The same with clusters replaced by their dipoles only beyond @a beta times their radius.
  double evaluate(const glm::dvec3& p, double beta) const;

  /// @brief Whether @a p is inside by the winding number, w >= 1/2. Where evaluate() lies within kRecheckBand of
  ///        1/2 the sum is taken again with kRecheckBetaFactor times beta: beside a rim the dipoles' error can
  ///        exceed the distance from 1/2 (it signed voxels of the open teapot wrongly). Still within kExactBand of
  ///        1/2, every triangle is summed (evaluateExact): rare, and then exact. The GPU's refinement follows the
  ///        same steps (open_winding.glsl: kWindingRecheckBand, kWindingExactBand; WindingExactPass).
  bool inside(const glm::dvec3& p) const;
  static constexpr double kRecheckBand = 0.1;
  static constexpr double kRecheckBetaFactor = 2.0;
  static constexpr double kExactBand = 0.05;

  /// @brief The exact winding number by summing every triangle's solid angle (slow: near 1/2 only, and tests).
  double evaluateExact(const glm::dvec3& p) const;

private:
  struct Node {
    glm::dvec3 center;     // area-weighted centroid
    glm::dvec3 areaNormal; // sum of the triangles' vector areas
    double radius;         // of a ball around center holding every vertex of the cluster
    int first, count;      // triangle range (leaves)
    int left, right;       // children, -1 for leaves
  };
  struct Builder;
  double solidAngle(int tri, const glm::dvec3& p) const;

  std::vector<glm::dvec3> mA, mB, mC; // triangle corners, reordered by the tree
  std::vector<Node> mNodes;
  double mBeta;
};

} // namespace rtsdf
