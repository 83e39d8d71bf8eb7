#include "reference/WindingNumber.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace rtsdf {
namespace {
constexpr int kLeafSize = 8;
constexpr int kParallelBuild = 1 << 14; // subtrees this large build their halves in parallel
constexpr double kInv4Pi = 1.0 / (4.0 * M_PI);
} // namespace

/// Builds the tree top down by median splits of the centroids. Per-triangle vector areas and centroids are
/// computed once; a node's index is known before its subtree is built (the shape depends on the counts alone), so
/// large subtrees build in parallel.
struct WindingNumberTree::Builder {
  WindingNumberTree& tree;
  std::vector<glm::dvec3> vectorArea, centroid;
  std::vector<int> order; // triangle of each slot; the leaves' ranges index it
  std::map<int, int> nodes; // nodes of a subtree over that many triangles

  /// Fills the table for @a count and every subtree below it (before the build, which only reads it).
  int nodesFor(int count) {
    if (count <= kLeafSize) return 1;
    const auto it = nodes.find(count);
    if (it != nodes.end()) return it->second;
    const int n = 1 + nodesFor(count / 2) + nodesFor(count - count / 2);
    nodes.emplace(count, n);
    return n;
  }
  int subtreeNodes(int count) const { return count <= kLeafSize ? 1 : nodes.at(count); }

  /// Node @a index over the slots [first, first + count).
  void build(int index, int first, int count) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY), weighted(0.0), areaNormal(0.0);
    double area = 0.0;
    for (int i = first; i < first + count; ++i) {
      const int t = order[std::size_t(i)];
      const double a = glm::length(vectorArea[std::size_t(t)]);
      weighted += a * centroid[std::size_t(t)];
      area += a;
      areaNormal += vectorArea[std::size_t(t)];
      lo = glm::min(lo, centroid[std::size_t(t)]);
      hi = glm::max(hi, centroid[std::size_t(t)]);
    }
    Node node{};
    node.center = area > 0.0 ? weighted / area : 0.5 * (lo + hi);
    node.areaNormal = areaNormal;
    double r2 = 0.0;
    for (int i = first; i < first + count; ++i) {
      const std::size_t t = std::size_t(order[std::size_t(i)]);
      for (const glm::dvec3* v : {&tree.mA[t], &tree.mB[t], &tree.mC[t]}) {
        const glm::dvec3 d = *v - node.center;
        r2 = std::max(r2, glm::dot(d, d));
      }
    }
    node.radius = std::sqrt(r2);
    node.first = first;
    node.count = count;
    node.left = node.right = -1;
    if (count > kLeafSize) {
      // Median split of the centroids along the widest axis.
      const glm::dvec3 ext = hi - lo;
      const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
      const int mid = count / 2;
      const auto begin = order.begin() + first;
      std::nth_element(begin, begin + mid, begin + count, [&](int x, int y) {
        return centroid[std::size_t(x)][axis] < centroid[std::size_t(y)][axis];
      });
      node.left = index + 1;
      node.right = index + 1 + subtreeNodes(mid);
      auto left = [&] { build(node.left, first, mid); };
      auto right = [&] { build(node.right, first + mid, count - mid); };
      if (count >= kParallelBuild) tbb::parallel_invoke(left, right);
      else { left(); right(); }
    }
    tree.mNodes[std::size_t(index)] = node;
  }
};

WindingNumberTree::WindingNumberTree(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                                     double beta)
    : mBeta(beta) {
  const std::size_t n = triangles.size();
  mA.resize(n); mB.resize(n); mC.resize(n);
  Builder b{*this, std::vector<glm::dvec3>(n), std::vector<glm::dvec3>(n), std::vector<int>(n), {}};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      mA[t] = glm::dvec3(positions[triangles[t].x]);
      mB[t] = glm::dvec3(positions[triangles[t].y]);
      mC[t] = glm::dvec3(positions[triangles[t].z]);
      b.vectorArea[t] = 0.5 * glm::cross(mB[t] - mA[t], mC[t] - mA[t]);
      b.centroid[t] = (mA[t] + mB[t] + mC[t]) / 3.0;
    }
  });
  if (!n) return;
  std::iota(b.order.begin(), b.order.end(), 0);
  mNodes.resize(std::size_t(b.nodesFor(int(n))));
  b.build(0, 0, int(n));
  // The leaves index slots: put the corners in slot order.
  std::vector<glm::dvec3> a(n), bb(n), c(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t t = std::size_t(b.order[i]);
    a[i] = mA[t]; bb[i] = mB[t]; c[i] = mC[t];
  }
  mA = std::move(a); mB = std::move(bb); mC = std::move(c);
}

double WindingNumberTree::solidAngle(int t, const glm::dvec3& p) const {
  // Van Oosterom and Strackee's formula for the signed solid angle of a triangle seen from p.
  const glm::dvec3 a = mA[t] - p, b = mB[t] - p, c = mC[t] - p;
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double det = glm::dot(a, glm::cross(b, c));
  const double div = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
  return 2.0 * std::atan2(det, div);
}

bool WindingNumberTree::inside(const glm::dvec3& p) const {
  // Each finer sum re-walks only the clusters the coarser one took as dipoles within the finer beta: the triangles
  // summed one by one and the clusters far enough for both are kept.
  Marginal first, second;
  double w = walk(p, nullptr, 0, mBeta, &first, kRecheckBetaFactor * mBeta) * kInv4Pi;
  if (std::fabs(w - 0.5) >= kRecheckBand) return w >= 0.5;
  const double beta2 = kRecheckBetaFactor * mBeta, beta3 = kFinalBetaFactor * mBeta;
  w = first.complete ? w + (walk(p, first.nodes, first.count, beta2, &second, beta3) - first.sum) * kInv4Pi
                     : walk(p, nullptr, 0, beta2, &second, beta3) * kInv4Pi;
  if (std::fabs(w - 0.5) >= kFinalBand) return w >= 0.5;
  w = second.complete ? w + (walk(p, second.nodes, second.count, beta3, nullptr, 0.0) - second.sum) * kInv4Pi
                      : evaluate(p, beta3);
  return w >= 0.5;
}

double WindingNumberTree::evaluate(const glm::dvec3& p, double beta) const {
  return walk(p, nullptr, 0, beta, nullptr, 0.0) * kInv4Pi;
}

double WindingNumberTree::walk(const glm::dvec3& p, const int* start, int starts, double beta, Marginal* marginal,
                               double finerBeta) const {
  if (mNodes.empty()) return 0.0;
  double sum = 0.0;
  int stack[Marginal::kMaxMarginal + 128]; // the start nodes, then a depth-first walk's two per level
  int top = 0;
  if (start) {
    for (int i = 0; i < starts; ++i) stack[top++] = start[i];
  } else {
    stack[top++] = 0;
  }
  while (top) {
    const int index = stack[--top];
    const Node& n = mNodes[std::size_t(index)];
    const glm::dvec3 d = n.center - p;
    const double dist2 = glm::dot(d, d);
    if (dist2 > beta * beta * n.radius * n.radius) {
      // Far field: the cluster acts as a dipole of strength areaNormal at its centre.
      const double dipole = glm::dot(d, n.areaNormal) / (dist2 * std::sqrt(dist2));
      sum += dipole;
      if (marginal && dist2 <= finerBeta * finerBeta * n.radius * n.radius) marginal->add(index, dipole);
      continue;
    }
    if (n.left < 0) {
      for (int t = n.first; t < n.first + n.count; ++t) sum += solidAngle(t, p);
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
  return sum;
}

double WindingNumberTree::evaluateExact(const glm::dvec3& p) const {
  double sum = 0.0;
  for (int t = 0; t < int(mA.size()); ++t) sum += solidAngle(t, p);
  return sum * kInv4Pi;
}

} // namespace rtsdf
