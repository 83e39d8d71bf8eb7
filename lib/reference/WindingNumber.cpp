#include "reference/WindingNumber.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rtsdf {
namespace {
constexpr int kLeafSize = 8;
constexpr double kInv4Pi = 1.0 / (4.0 * M_PI);
} // namespace

WindingNumberTree::WindingNumberTree(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                                     double beta)
    : mBeta(beta) {
  const std::size_t n = triangles.size();
  mA.resize(n); mB.resize(n); mC.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    mA[t] = glm::dvec3(positions[triangles[t].x]);
    mB[t] = glm::dvec3(positions[triangles[t].y]);
    mC[t] = glm::dvec3(positions[triangles[t].z]);
  }
  mNodes.reserve(2 * n / kLeafSize + 2);
  if (n) build(0, int(n));
}

int WindingNumberTree::build(int first, int count) {
  const int index = int(mNodes.size());
  mNodes.push_back({});
  glm::dvec3 lo(INFINITY), hi(-INFINITY), weighted(0.0), areaNormal(0.0);
  double area = 0.0;
  for (int t = first; t < first + count; ++t) {
    const glm::dvec3 va = 0.5 * glm::cross(mB[t] - mA[t], mC[t] - mA[t]);
    const double a = glm::length(va);
    const glm::dvec3 centroid = (mA[t] + mB[t] + mC[t]) / 3.0;
    weighted += a * centroid;
    area += a;
    areaNormal += va;
    lo = glm::min(lo, centroid);
    hi = glm::max(hi, centroid);
  }
  Node node{};
  node.center = area > 0.0 ? weighted / area : 0.5 * (lo + hi);
  node.areaNormal = areaNormal;
  double r2 = 0.0;
  for (int t = first; t < first + count; ++t)
    for (const glm::dvec3* v : {&mA[t], &mB[t], &mC[t]}) {
      const glm::dvec3 d = *v - node.center;
      r2 = std::max(r2, glm::dot(d, d));
    }
  node.radius = std::sqrt(r2);
  node.first = first;
  node.count = count;
  node.left = node.right = -1;
  if (count > kLeafSize) {
    // Median split of the centroids along the widest axis.
    const glm::dvec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::vector<int> order(count);
    std::iota(order.begin(), order.end(), first);
    const int mid = count / 2;
    std::nth_element(order.begin(), order.begin() + mid, order.end(), [&](int x, int y) {
      return (mA[x][axis] + mB[x][axis] + mC[x][axis]) < (mA[y][axis] + mB[y][axis] + mC[y][axis]);
    });
    std::vector<glm::dvec3> a(count), b(count), c(count);
    for (int i = 0; i < count; ++i) { a[i] = mA[order[i]]; b[i] = mB[order[i]]; c[i] = mC[order[i]]; }
    std::copy(a.begin(), a.end(), mA.begin() + first);
    std::copy(b.begin(), b.end(), mB.begin() + first);
    std::copy(c.begin(), c.end(), mC.begin() + first);
    node.left = build(first, mid);
    node.right = build(first + mid, count - mid);
  }
  mNodes[index] = node;
  return index;
}

double WindingNumberTree::solidAngle(int t, const glm::dvec3& p) const {
  // Van Oosterom and Strackee's formula for the signed solid angle of a triangle seen from p.
  const glm::dvec3 a = mA[t] - p, b = mB[t] - p, c = mC[t] - p;
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double det = glm::dot(a, glm::cross(b, c));
  const double div = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
  return 2.0 * std::atan2(det, div);
}

double WindingNumberTree::evaluate(const glm::dvec3& p) const {
  if (mNodes.empty()) return 0.0;
  double sum = 0.0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top) {
    const Node& n = mNodes[stack[--top]];
    const glm::dvec3 d = n.center - p;
    const double dist2 = glm::dot(d, d);
    if (dist2 > mBeta * mBeta * n.radius * n.radius) {
      // Far field: the cluster acts as a dipole of strength areaNormal at its centre.
      sum += glm::dot(d, n.areaNormal) / (dist2 * std::sqrt(dist2));
      continue;
    }
    if (n.left < 0) {
      for (int t = n.first; t < n.first + n.count; ++t) sum += solidAngle(t, p);
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
  return sum * kInv4Pi;
}

double WindingNumberTree::evaluateExact(const glm::dvec3& p) const {
  double sum = 0.0;
  for (int t = 0; t < int(mA.size()); ++t) sum += solidAngle(t, p);
  return sum * kInv4Pi;
}

} // namespace rtsdf
