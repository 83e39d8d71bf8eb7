#pragma once
// .vdb files that are not what compare may measure, or that it used to misread: a fog volume named "surface", a
// double level set, non-cubic voxels, a frustum transform, a NaN voxel, two candidate level sets, level sets held
// in active tiles, and two bakes of different scenes. Shared by the compare tests and the bad-input table's
// fixtures.
#include "TestUtil.h"
#include "grid/VdbIO.h"

#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>
#include <limits>

namespace rtsdf::test {

/// A sphere of radius 0.5 at @a centre on a grid of voxel size 1/32 around the origin, band three voxels.
inline openvdb::FloatGrid::Ptr sphereLevelSet(const glm::dvec3& centre = {0, 0, 0}) {
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 64, 0.25);
  auto grid = denseToLevelSet(sphereField(g, centre, 0.5), g, float(3 * g.voxelSize));
  stampLevelSet(*grid, g, {{"method", "test"}});
  return grid;
}

/// A level set of voxel size 1 whose active values (@a value) are tiles of 8^3 voxels filling @a box: no leaf.
inline openvdb::FloatGrid::Ptr tileLevelSet(const openvdb::CoordBBox& box, float value) {
  auto grid = openvdb::FloatGrid::create(3.0f);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName("surface");
  grid->tree().fill(box, value, /*active=*/true);
  return grid;
}

/// Every file above in @a dir: fog.vdb, double.vdb, nonuniform.vdb, frustum.vdb, nan.vdb, two.vdb (level sets
/// 'left' and 'right'), tiles_a.vdb and tiles_b.vdb (tiles overlapping in 8^3 voxels, values 0.1 and 0.2),
/// scene_a.vdb and scene_b.vdb (one sphere recorded as baked from two scenes).
inline void writeLevelSetFiles(const std::filesystem::path& dir) {
  auto fog = sphereLevelSet()->deepCopy();
  openvdb::tools::sdfToFogVolume(*fog);
  fog->setName("surface");
  writeVdb(dir / "fog.vdb", {fog});

  auto sphere = sphereLevelSet();
  auto dbl = openvdb::DoubleGrid::create(double(sphere->background()));
  for (auto it = sphere->cbeginValueOn(); it; ++it) dbl->tree().setValue(it.getCoord(), double(*it));
  dbl->setGridClass(openvdb::GRID_LEVEL_SET);
  dbl->setName("surface");
  writeVdb(dir / "double.vdb", {dbl});

  auto nonUniform = sphereLevelSet()->deepCopy();
  nonUniform->setTransform(openvdb::math::Transform::createLinearTransform(
      openvdb::Mat4d(1.0 / 32, 0.0, 0.0, 0.0, 0.0, 1.0 / 32, 0.0, 0.0, 0.0, 0.0, 1.0 / 16, 0.0, 0.0, 0.0, 0.0, 1.0)));
  writeVdb(dir / "nonuniform.vdb", {nonUniform});

  auto frustum = sphereLevelSet()->deepCopy();
  frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(63)), 0.5, 2.0, 1.0 / 32));
  writeVdb(dir / "frustum.vdb", {frustum});

  auto nan = sphereLevelSet()->deepCopy();
  nan->tree().setValue(nan->cbeginValueOn().getCoord(), std::numeric_limits<float>::quiet_NaN());
  writeVdb(dir / "nan.vdb", {nan});

  auto left = sphereLevelSet(), right = sphereLevelSet({0.1, 0, 0});
  left->setName("left");
  right->setName("right");
  writeVdb(dir / "two.vdb", {left, right});

  writeVdb(dir / "tiles_a.vdb", {tileLevelSet(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)), 0.1f)});
  writeVdb(dir / "tiles_b.vdb", {tileLevelSet(openvdb::CoordBBox(openvdb::Coord(8), openvdb::Coord(23)), 0.2f)});

  for (const char* scene : {"a", "b"}) {
    auto baked = sphereLevelSet();
    const std::string path = std::string("/scenes/") + scene + ".obj";
    stampLevelSet(*baked, gridSpecOf(*baked), {{"method", "test"}, {"scene", path}});
    writeVdb(dir / (std::string("scene_") + scene + ".vdb"), {baked});
  }
}

} // namespace rtsdf::test
