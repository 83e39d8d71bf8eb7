#pragma once
/// @file SceneGeometry.h
/// @brief The scene's triangles in world space at one moment: what the SDF builders consume.
#include "scene/Scene.h"
#include "util/Bounds.h"

#include <string>
#include <vector>

namespace rtsdf {

/// @brief One instance's mesh transformed to world space.
struct WorldMesh {
  std::string instance;             ///< instance name
  std::string source;               ///< mesh source (file) for messages
  std::vector<glm::vec3> positions; ///< world space
  std::vector<glm::uvec3> triangles;
  bool watertight = false;          ///< closed, manifold and consistently oriented
};

/// @brief All instances of a scene in world space.
struct SceneGeometry {
  std::vector<WorldMesh> meshes;
  Bounds bounds;
  std::size_t triangleCount() const;
};

/// @brief Every triangle as three world-space corners (w = 1), instance by instance: the GPU upload format.
std::vector<glm::vec4> triangleCorners(const SceneGeometry& geometry);

/// @brief Transform every instance of @a scene to world space at @a time seconds.
/// @note A mirroring transform (negative determinant) reverses triangle winding so outside stays outside.
/// @note Triangles that a transform rounds to zero area in float are dropped with a warning (Embree would
///       skip them silently).
/// @throw Error when a transform turns coordinates non-finite or leaves an instance no triangle.
SceneGeometry buildSceneGeometry(const Scene& scene, double time = 0.0);

} // namespace rtsdf
