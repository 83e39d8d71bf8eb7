#pragma once
/// @file Bounds.h
/// @brief An axis-aligned box in world space (double precision), and the finiteness of a point.
#include <glm/glm.hpp>

#include <cmath>
#include <limits>

namespace rtsdf {

/// @brief Whether every coordinate of @a v is finite (neither infinite nor NaN).
inline bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// @brief Axis-aligned bounds; empty until a point is added.
struct Bounds {
  glm::dvec3 min{std::numeric_limits<double>::infinity()};
  glm::dvec3 max{-std::numeric_limits<double>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  void add(const glm::dvec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
  void add(const Bounds& b) { if (!b.empty()) { add(b.min); add(b.max); } }
  glm::dvec3 extent() const { return empty() ? glm::dvec3(0.0) : max - min; }
  glm::dvec3 center() const { return 0.5 * (min + max); }
  double maxExtent() const { const glm::dvec3 e = extent(); return glm::max(e.x, glm::max(e.y, e.z)); }
  /// Whether this box and @a o share a point (touching counts); never for an empty one.
  bool meets(const Bounds& o) const {
    return !empty() && !o.empty() && glm::all(glm::lessThanEqual(min, o.max)) &&
           glm::all(glm::lessThanEqual(o.min, max));
  }
};

} // namespace rtsdf
