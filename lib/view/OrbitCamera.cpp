#include "view/OrbitCamera.h"

#include "util/Error.h"

#include <algorithm>
#include <cmath>

namespace rtsdf {
namespace {
constexpr double kMaxPitch = 89.0 * 3.14159265358979323846 / 180.0;
}

OrbitCamera OrbitCamera::from(const Camera& c) {
  const glm::dvec3 d = c.position - c.target;
  const double r = glm::length(d);
  if (!(r > 0.0)) throw Error("the camera's position equals its target: nothing to orbit");
  OrbitCamera o;
  o.target = c.target;
  o.distance = r;
  o.pitch = std::clamp(std::asin(std::clamp(d.y / r, -1.0, 1.0)), -kMaxPitch, kMaxPitch);
  o.yaw = std::atan2(d.x, d.z);
  o.verticalFov = c.verticalFov;
  return o;
}

Camera OrbitCamera::camera() const {
  Camera c;
  c.target = target;
  c.position = target + distance * glm::dvec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                               std::cos(pitch) * std::cos(yaw));
  c.up = glm::dvec3(0.0, 1.0, 0.0);
  c.verticalFov = verticalFov;
  return c;
}

void OrbitCamera::rotate(double dYaw, double dPitch) {
  yaw = std::remainder(yaw + dYaw, 2.0 * 3.14159265358979323846);
  pitch = std::clamp(pitch + dPitch, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::zoom(double steps) {
  // Bounded both ways: a flung wheel neither puts the eye on the target nor sends it to infinity.
  distance = std::clamp(distance * std::pow(0.9, std::clamp(steps, -100.0, 100.0)), 1e-6, 1e9);
}

} // namespace rtsdf
