#include "scene/SceneGeometry.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

std::size_t SceneGeometry::triangleCount() const {
  std::size_t n = 0;
  for (const WorldMesh& m : meshes) n += m.triangles.size();
  return n;
}

void requireWorldFrame(const SceneGeometry& geometry, const char* user) {
  if (geometry.origin != glm::dvec3(0.0))
    throw Error(fmt::format("{}: needs world coordinates, but the geometry is measured from ({}, {}, {})", user,
                            geometry.origin.x, geometry.origin.y, geometry.origin.z));
}

std::vector<glm::vec4> triangleCorners(const SceneGeometry& geometry) {
  std::vector<glm::vec4> out;
  out.reserve(3 * geometry.triangleCount());
  for (const WorldMesh& m : geometry.meshes)
    for (const glm::uvec3& t : m.triangles)
      for (int c = 0; c < 3; ++c) out.emplace_back(m.positions[t[c]], 1.0f);
  return out;
}

SceneGeometry buildSceneGeometry(const Scene& scene, double time, const glm::dvec3& origin) {
  SceneGeometry geo;
  geo.origin = origin;
  geo.meshes.reserve(scene.instances.size());
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes.at(inst.mesh);
    const glm::dmat4 m = inst.matrixAt(time);
    WorldMesh w;
    w.instance = inst.name;
    w.source = mesh.source;
    w.watertight = scene.meshReports.at(inst.mesh).watertight();
    w.positions.reserve(mesh.positions.size());
    for (const glm::vec3& p : mesh.positions) {
      const glm::dvec3 world = glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0));
      const glm::dvec3 q = world - origin;
      const glm::vec3 f(q);
      if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z))
        throw Error(fmt::format("{}: instance '{}' moves a vertex to a non-finite position at time {}", scene.path,
                                inst.name, time));
      const double far = std::max({std::abs(world.x), std::abs(world.y), std::abs(world.z)});
      if (far > kMaxCoordinate)
        throw Error(fmt::format("{}: instance '{}' moves a vertex to the coordinate {:g} at time {}, beyond the ±{:g} "
                                "rtsdf supports (float precision): scale the scene down", scene.path, inst.name, far,
                                time, kMaxCoordinate));
      w.positions.push_back(f);
      // In double: grids placed from these bounds sit where they would at the world's origin, to the voxel.
      geo.bounds.add(q);
    }
    const bool mirrored = glm::determinant(glm::dmat3(m)) < 0.0;
    w.triangles.reserve(mesh.triangles.size());
    std::size_t collapsed = 0;
    for (glm::uvec3 t : mesh.triangles) {
      // A tiny scale can round a valid triangle to zero area in float: Embree would silently skip it.
      if (!hasFloatArea(w.positions[t.x], w.positions[t.y], w.positions[t.z])) { ++collapsed; continue; }
      if (mirrored) std::swap(t.y, t.z);
      w.triangles.push_back(t);
    }
    if (collapsed)
      spdlog::warn("{}: instance '{}': {} of {} triangles have zero area in world space (float rounding of its "
                   "transform) and were dropped", scene.path, inst.name, collapsed, mesh.triangles.size());
    if (w.triangles.empty())
      throw Error(fmt::format("{}: instance '{}' has no triangle of non-zero area in world space", scene.path,
                              inst.name));
    geo.meshes.push_back(std::move(w));
  }
  return geo;
}

void checkInstancePlacement(const Scene& scene, const std::vector<Bounds>& meshBounds, double time) {
  for (const Instance& inst : scene.instances) {
    const Bounds& box = meshBounds.at(inst.mesh);
    if (box.empty()) continue;
    const glm::dmat4 m = inst.matrixAt(time);
    // Every vertex lies in its mesh's box, so its image lies in the hull of the corners' images.
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec4 p((corner & 1 ? box.max : box.min).x, (corner & 2 ? box.max : box.min).y,
                         (corner & 4 ? box.max : box.min).z, 1.0);
      const glm::dvec3 world(m * p);
      if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z))
        throw Error(fmt::format("{}: instance '{}' moves its mesh's bounds to a non-finite position at time {}",
                                scene.path, inst.name, time));
      const double far = std::max({std::abs(world.x), std::abs(world.y), std::abs(world.z)});
      if (far > kMaxCoordinate)
        throw Error(fmt::format("{}: instance '{}' moves its mesh's bounds to the coordinate {:g} at time {}, beyond "
                                "the ±{:g} rtsdf supports (float precision): scale the scene down", scene.path,
                                inst.name, far, time, kMaxCoordinate));
    }
  }
}

} // namespace rtsdf
