#include "sdf/pipeline/ViewReach.h"

#include "util/Error.h"

#include <algorithm>
#include <cmath>

namespace rtsdf {

ViewReach viewReachOf(const Camera& camera, double aspect, double margin) {
  const glm::dvec3 forward = camera.target - camera.position;
  const double length = glm::length(forward);
  if (!(length > 0.0) || !std::isfinite(length))
    throw Error("view reach: the camera looks at its own position (no view direction)");
  if (!(aspect > 0.0) || !std::isfinite(aspect)) throw Error("view reach: the image's aspect must be positive");
  ViewReach r;
  r.apex = camera.position;
  r.axis = forward / length;
  // The image's corner lies tan(fov / 2) up and aspect times that across, at unit distance along the axis.
  const double corner = std::tan(0.5 * camera.verticalFov) * std::sqrt(1.0 + aspect * aspect);
  r.halfAngle = std::min(std::atan(corner), kMaxViewHalfAngle);
  r.margin = margin;
  return r;
}

} // namespace rtsdf
