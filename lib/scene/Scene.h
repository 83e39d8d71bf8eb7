#pragma once
/// @file Scene.h
/// @brief A scene: meshes, rigid instances (optionally animated), lights and a camera.
#include "scene/Mesh.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <string>
#include <vector>

namespace rtsdf {

/// @brief A rigid transform with scale: world = T * R * S * local.
struct Transform {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
  glm::dmat4 matrix() const;
};

/// @brief One keyframe of an instance's animation (time in seconds).
struct Keyframe {
  double time = 0.0;
  Transform transform;
};

/// @brief Rigid animation of an instance; the base transform is applied first, the animation after it.
struct Animation {
  /// @brief How the instance moves.
  enum class Kind {
    None,      ///< static
    Keyframes, ///< piecewise linear translation/scale and slerped rotation between keyframes, clamped at the ends
    Orbit      ///< circular orbit of the base position about an axis through a centre
  };
  Kind kind = Kind::None;
  std::vector<Keyframe> keyframes; ///< sorted by time (Keyframes)
  glm::dvec3 center{0.0};          ///< Orbit: centre of the circle
  glm::dvec3 axis{0.0, 1.0, 0.0};  ///< Orbit: unit rotation axis
  double period = 1.0;             ///< Orbit: seconds per revolution (> 0)
  double phase = 0.0;              ///< Orbit: starting angle in radians
  bool faceAlong = true;           ///< Orbit: rotate the instance with the orbit (like a carousel)
};

/// @brief A placement of a mesh in the scene.
struct Instance {
  std::string name;
  std::size_t mesh = 0; ///< index into Scene::meshes
  Transform transform;
  Animation animation;
  /// @brief The instance's object-to-world matrix at @a time seconds.
  glm::dmat4 matrixAt(double time) const;
};

/// @brief A light: directional (with an angular radius, a soft sun) or a sphere light.
struct Light {
  enum class Type { Directional, Sphere };
  std::string name;
  Type type = Type::Directional;
  glm::dvec3 direction{0.0, -1.0, 0.0}; ///< Directional: unit direction the light travels
  double angularRadius = 0.0;           ///< Directional: half-angle of the sun disc, radians
  glm::dvec3 position{0.0};             ///< Sphere: centre
  double radius = 0.0;                  ///< Sphere: radius
  glm::dvec3 color{1.0};
  double intensity = 1.0;
};

/// @brief A pinhole camera.
struct Camera {
  glm::dvec3 position{0.0, 1.0, 3.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double verticalFov = 0.785398; ///< radians
};

/// @brief One keyframe of the scene camera's path (time in seconds); `up` stays the camera's.
struct CameraKeyframe {
  double time = 0.0;
  glm::dvec3 position{0.0};
  glm::dvec3 target{0.0};
  double verticalFov = 0.785398; ///< radians
};

/// @brief Everything a scene file describes. Meshes are validated when loaded.
struct Scene {
  std::string path; ///< the file it was loaded from
  std::vector<Mesh> meshes;
  std::vector<MeshReport> meshReports; ///< parallel to meshes
  std::vector<Instance> instances;
  std::vector<Light> lights;
  Camera camera;      ///< the camera at time 0 (the path's first keyframe when there is a path)
  bool hasCamera = false;
  /// @brief The camera's path, sorted by time; empty for a fixed camera. Interpolated like instance keyframes:
  ///        position, target and field of view linearly between keyframes, clamped at the ends.
  std::vector<CameraKeyframe> cameraPath;
  /// @brief The camera at @a time seconds: `camera` when there is no path.
  Camera cameraAt(double time) const;
};

} // namespace rtsdf
