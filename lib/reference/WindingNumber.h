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
  ///        1/2 the sum is taken again with kRecheckBetaFactor times beta: beside a rim the dipoles' error (up to
  ///        about 0.03) can exceed the distance from 1/2 (it signed 13 of 601 such points of the open teapot
  ///        wrongly). Still within kFinalBand of 1/2, once more with kFinalBetaFactor times beta (the dipoles' error
  ///        falls with the square of beta: a few 1e-3). Each finer sum re-walks only the clusters the coarser one
  ///        took as dipoles within the finer beta. Not every triangle: beside the holes and slits of open scans of
  ///        230k-320k triangles, where w is near 1/2 at many points, brute-force sums made the bake 3-6 times
  ///        OpenVDB's. The GPU's refinement sums every triangle there (open_winding.glsl: kWindingExactBand;
  ///        WindingExactPass).
  bool inside(const glm::dvec3& p) const;
  static constexpr double kRecheckBand = 0.05;
  static constexpr double kRecheckBetaFactor = 2.0;
  static constexpr double kFinalBand = 0.02;
  static constexpr double kFinalBetaFactor = 4.0;

  /// @brief The exact winding number by summing every triangle's solid angle (slow; for tests).
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
  /// The clusters a walk took as dipoles that a finer beta would open, and their dipoles' sum (up to kMaxMarginal;
  /// past that, not complete: the finer sum walks the whole tree).
  struct Marginal {
    static constexpr int kMaxMarginal = 1024;
    int nodes[kMaxMarginal];
    int count = 0;
    double sum = 0.0;
    bool complete = true;
    void add(int node, double dipole) {
      sum += dipole;
      if (count < kMaxMarginal) nodes[count++] = node;
      else complete = false;
    }
  };
  /// The solid angles (not divided by 4 pi) of the subtrees at @a start (the root when null), clusters farther than
  /// @a beta radii by their dipoles; those within @a finerBeta radii noted in @a marginal (when not null).
  double walk(const glm::dvec3& p, const int* start, int starts, double beta, Marginal* marginal,
              double finerBeta) const;

  std::vector<glm::dvec3> mA, mB, mC; // triangle corners, reordered by the tree
  std::vector<Node> mNodes;
  double mBeta;
};

} // namespace rtsdf
