#include "scene/Scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace rtsdf {

glm::dmat4 Transform::matrix() const {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), translation);
  m = m * glm::mat4_cast(rotation);
  return glm::scale(m, scale);
}

namespace {

Transform lerp(const Transform& a, const Transform& b, double s) {
  Transform t;
  t.translation = glm::mix(a.translation, b.translation, s);
  t.scale = glm::mix(a.scale, b.scale, s);
  t.rotation = glm::slerp(a.rotation, b.rotation, s);
  return t;
}

} // namespace

glm::dmat4 Instance::matrixAt(double time) const {
  const glm::dmat4 base = transform.matrix();
  switch (animation.kind) {
  case Animation::Kind::None:
    return base;
  case Animation::Kind::Keyframes: {
    const auto& k = animation.keyframes;
    if (k.empty()) return base;
    if (time <= k.front().time) return k.front().transform.matrix() * base;
    if (time >= k.back().time) return k.back().transform.matrix() * base;
    const auto hi = std::upper_bound(k.begin(), k.end(), time,
                                     [](double t, const Keyframe& f) { return t < f.time; });
    const auto lo = hi - 1;
    const double span = hi->time - lo->time;
    const double s = span > 0.0 ? (time - lo->time) / span : 0.0;
    return lerp(lo->transform, hi->transform, s).matrix() * base;
  }
  case Animation::Kind::Orbit: {
    const double angle = animation.phase + 2.0 * M_PI * time / animation.period;
    const glm::dmat4 toCenter = glm::translate(glm::dmat4(1.0), animation.center);
    const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), angle, animation.axis);
    const glm::dmat4 fromCenter = glm::translate(glm::dmat4(1.0), -animation.center);
    glm::dmat4 m = toCenter * rot * fromCenter * base;
    if (!animation.faceAlong) {
      // Move along the circle but keep the base orientation.
      const glm::dvec3 p = glm::dvec3(m[3]);
      m = glm::translate(glm::dmat4(1.0), p - glm::dvec3(base[3])) * base;
    }
    return m;
  }
  }
  return base;
}

Camera Scene::cameraAt(double time) const {
  if (cameraPath.empty()) return camera;
  Camera c = camera;
  const auto set = [&c](const CameraKeyframe& k) {
    c.position = k.position;
    c.target = k.target;
    c.verticalFov = k.verticalFov;
  };
  if (time <= cameraPath.front().time) return set(cameraPath.front()), c;
  if (time >= cameraPath.back().time) return set(cameraPath.back()), c;
  const auto hi = std::upper_bound(cameraPath.begin(), cameraPath.end(), time,
                                   [](double t, const CameraKeyframe& f) { return t < f.time; });
  const auto lo = hi - 1;
  const double span = hi->time - lo->time;
  const double s = span > 0.0 ? (time - lo->time) / span : 0.0;
  c.position = glm::mix(lo->position, hi->position, s);
  c.target = glm::mix(lo->target, hi->target, s);
  c.verticalFov = lo->verticalFov + s * (hi->verticalFov - lo->verticalFov);
  return c;
}

} // namespace rtsdf
