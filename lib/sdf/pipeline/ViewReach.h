#pragma once
/// @file ViewReach.h
/// @brief Where a pipeline refines when a camera's view limits it (cascade levels above 0): the band within a margin
///        of the cone around the camera's view direction that holds the image. The rest keeps the coarse SDF.
#include "scene/Scene.h"

#include <glm/glm.hpp>

namespace rtsdf {

/// @brief A camera's view cone widened by a margin (world units, the GPU passes measure from their frame's origin).
struct ViewReach {
  glm::dvec3 apex{0.0};            ///< the camera's position
  glm::dvec3 axis{0.0, 0.0, -1.0}; ///< the unit view direction
  double halfAngle = 0.5;          ///< radians, in (0, kMaxViewHalfAngle]: the cone reaches the image's corners
  double margin = 0.0;             ///< scene units beyond the cone still refined
  bool operator==(const ViewReach& o) const {
    return apex == o.apex && axis == o.axis && halfAngle == o.halfAngle && margin == o.margin;
  }
  bool operator!=(const ViewReach& o) const { return !(*this == o); }
};

/// @brief The widest half-angle a ViewReach takes (89 degrees): a wider view is held by that cone's margin anyway.
constexpr double kMaxViewHalfAngle = 1.5533430342749532;

/// @brief The cone holding the image of @a camera at @a aspect (width over height), widened by @a margin.
/// @throw Error when the camera looks at its own position or @a aspect is not positive and finite.
ViewReach viewReachOf(const Camera& camera, double aspect, double margin);

} // namespace rtsdf
