#include "reference/OpenVdbLevelSet.h"

#include "grid/VdbIO.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>

namespace rtsdf {
namespace {

void flatten(const SceneGeometry& geometry, std::vector<openvdb::Vec3s>& points, std::vector<openvdb::Vec3I>& tris) {
  requireWorldFrame(geometry, "OpenVDB level set");
  for (const WorldMesh& m : geometry.meshes) {
    const unsigned base = unsigned(points.size());
    for (const glm::vec3& p : m.positions) points.emplace_back(p.x, p.y, p.z);
    for (const glm::uvec3& t : m.triangles) tris.emplace_back(base + t.x, base + t.y, base + t.z);
  }
  if (tris.empty()) throw Error("OpenVDB level set: the scene has no triangles");
}

openvdb::FloatGrid::Ptr clipToSpec(openvdb::FloatGrid::Ptr grid, const GridSpec& spec) {
  const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(spec.dims.x - 1, spec.dims.y - 1, spec.dims.z - 1));
  grid->clip(box);
  return grid;
}

} // namespace

openvdb::FloatGrid::Ptr openvdbLevelSet(const SceneGeometry& geometry, const GridSpec& spec, double band) {
  if (!(band > 0.0) || !std::isfinite(band))
    throw Error(fmt::format("OpenVDB level set: band {} must be positive and finite", band));
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  flatten(geometry, points, tris);
  const auto xf = makeTransform(spec);
  const float halfWidth = std::max(1.0f, float(band / spec.voxelSize));
  auto grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xf, points, tris, halfWidth);
  return clipToSpec(grid, spec);
}

openvdb::FloatGrid::Ptr openvdbSignedDistanceField(const SceneGeometry& geometry, const GridSpec& spec) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  flatten(geometry, points, tris);
  const auto xf = makeTransform(spec);
  const float reach = float(glm::length(glm::dvec3(spec.dims)));
  auto grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xf, points, tris,
                                                                            std::vector<openvdb::Vec4I>(), reach, reach);
  return clipToSpec(grid, spec);
}

} // namespace rtsdf
