// The world geometry of one mesh for the reference tests, validated as a load would.
#pragma once

#include "scene/Mesh.h"
#include "scene/SceneGeometry.h"

#include <utility>

namespace rtsdf::test {

/// @brief The world geometry of @a mesh scaled by @a unit, validated (welded, oriented) as a load would.
inline SceneGeometry geometryOf(Mesh mesh, float unit = 1.0f) {
  for (glm::vec3& p : mesh.positions) p *= unit;
  const MeshReport r = validateMesh(mesh);
  SceneGeometry g;
  WorldMesh w;
  w.instance = mesh.name;
  w.source = mesh.source;
  w.positions = mesh.positions;
  w.triangles = mesh.triangles;
  w.watertight = r.watertight();
  for (const auto& p : w.positions) g.bounds.add(glm::dvec3(p));
  g.meshes.push_back(std::move(w));
  return g;
}

} // namespace rtsdf::test
