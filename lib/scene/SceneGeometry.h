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
  std::vector<glm::vec3> positions; ///< world space, relative to SceneGeometry::origin
  std::vector<glm::uvec3> triangles;
  bool watertight = false;          ///< closed, manifold and consistently oriented
};

/// @brief All instances of a scene in world space.
///
/// Positions and bounds are relative to @a origin (world = origin + position): a frame near the geometry keeps
/// float coordinates small, so a scene far from the world's origin keeps its precision (the GPU passes work
/// in the frame of their grid).
struct SceneGeometry {
  std::vector<WorldMesh> meshes;
  Bounds bounds;               ///< of the positions (relative to origin) before they were rounded to float
  glm::dvec3 origin{0.0};      ///< the world point the positions are measured from
  std::size_t triangleCount() const;
};

/// @brief Refuse geometry measured from a frame other than the world's, for @a user, whose outputs (grids,
///        images) are placed in world coordinates.
/// @throw Error naming @a user when geometry.origin is not (0, 0, 0).
void requireWorldFrame(const SceneGeometry& geometry, const char* user);

/// @brief Every triangle as three world-space corners (w = 1), instance by instance: the GPU upload format.
std::vector<glm::vec4> triangleCorners(const SceneGeometry& geometry);

/// @brief Transform every instance of @a scene to world space at @a time seconds.
/// @param origin the world point positions are measured from: each vertex is placed by M * p - origin in
///        double and only then rounded to float.
/// @note A mirroring transform (negative determinant) reverses triangle winding so outside stays outside.
/// @note Triangles that a transform rounds to zero area in float are dropped with a warning (Embree would
///       skip them silently).
/// @throw Error when a transform turns coordinates non-finite or leaves an instance no triangle.
SceneGeometry buildSceneGeometry(const Scene& scene, double time = 0.0, const glm::dvec3& origin = glm::dvec3(0.0));

/// @brief Check that every instance of @a scene keeps its vertices finite and within ±kMaxCoordinate at @a time,
///        from the 8 corners of its mesh's box (@a meshBounds, per mesh: positionBounds): the host's cost grows with
///        the instances, not their triangles. For frames whose triangles the GPU places (SdfPipeline).
/// @throw Error naming the scene and the instance when a box corner is non-finite or beyond ±kMaxCoordinate.
void checkInstancePlacement(const Scene& scene, const std::vector<Bounds>& meshBounds, double time);

} // namespace rtsdf
