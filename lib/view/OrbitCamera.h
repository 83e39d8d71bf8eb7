#pragma once
/// @file OrbitCamera.h
/// @brief The viewer's camera: it orbits the scene camera's target (drag to turn, scroll to come closer).
#include "scene/Scene.h"

#include <glm/glm.hpp>

namespace rtsdf {

/// @brief A camera on a sphere around a target: yaw about the world's up (+y), pitch above the horizon.
struct OrbitCamera {
  glm::dvec3 target{0.0};
  double yaw = 0.0;      ///< radians about +y; 0 looks along -z
  double pitch = 0.0;    ///< radians above the horizon (the camera looks down when positive), |pitch| < 89 deg
  double distance = 1.0; ///< from the target
  double verticalFov = 0.785398; ///< radians

  /// @brief The orbit through @a camera's position around its target.
  /// @throw Error when the camera's position equals its target.
  static OrbitCamera from(const Camera& camera);
  /// @brief The scene camera on the orbit (up: +y).
  Camera camera() const;
  /// @brief Turn by @a dYaw, @a dPitch radians (the pitch stays within 89 degrees of the horizon).
  void rotate(double dYaw, double dPitch);
  /// @brief Come closer (steps > 0) or go away by 10% per step; the distance stays within [1e-6, 1e9].
  void zoom(double steps);
};

} // namespace rtsdf
