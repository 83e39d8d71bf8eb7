// rtsdf mesh: the zero level set of a bake as a mesh file (OpenVDB's volumeToMesh, assimp's exporter) that stands
// where the scene does (within a voxel at thin tips, half a voxel on smooth sides), faces outward, in each format, Y-up or turned Z-up; bad requests refused
// with nothing written.
#include "TestUtil.h"
#include "LevelSetFiles.h"
#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/MeshJob.h"
#include "scene/MeshIO.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace rtsdf;
using rtsdf::test::TempDir;

namespace {

/// The bunny scene (data/scenes/bunny.json: bunny.obj scaled by 0.2) baked exactly at 64 voxels across.
const BakeResult& bunnyBake() {
  static const BakeResult r = [] {
    BakeOptions o;
    o.scene = test::dataPath("scenes/bunny.json");
    o.resolution = 64;
    return bake(o);
  }();
  return r;
}

Bounds bunnyBounds() {
  const Bounds b = positionBounds(loadMeshFile(test::dataPath("meshes/bunny.obj")));
  return {0.2 * b.min, 0.2 * b.max};
}

double farthestBound(const Bounds& a, const Bounds& b) {
  double d = 0.0;
  for (int i = 0; i < 3; ++i) d = std::max({d, std::fabs(a.min[i] - b.min[i]), std::fabs(a.max[i] - b.max[i])});
  return d;
}

} // namespace

TEST(MeshJob, TheBunnyBakesMeshLiesWithinAVoxelOfTheBunnysBoundsHalfOnItsSidesAndFacesOutward) {
  TempDir dir;
  writeBake(bunnyBake(), dir / "bunny.vdb");
  MeshOptions o;
  o.input = dir / "bunny.vdb";
  o.output = dir / "bunny.obj";
  const MeshResult r = meshLevelSet(o);
  const double h = bunnyBake().spec.voxelSize;
  EXPECT_NEAR(r.voxelSize, h, 1e-12); // the transform's, computed back from its matrix
  const Mesh mesh = loadMeshFile(o.output);
  EXPECT_EQ(mesh.triangles.size(), r.triangles);
  const Bounds want = bunnyBounds(), got = positionBounds(mesh);
  // Marching cubes places no vertex past the last voxel centre inside a feature thinner than a voxel: the ear tips
  // (top) end 0.84 voxel short at 64 voxels across (0.64 at 128). Where the surface is smooth, as on the sides
  // along x, the bounds agree within 0.13 voxel.
  EXPECT_LE(farthestBound(got, want), 1.0 * h) << "voxel " << h;
  EXPECT_LE(std::fabs(got.min.x - want.min.x), 0.5 * h);
  EXPECT_LE(std::fabs(got.max.x - want.max.x), 0.5 * h);
  EXPECT_LE(farthestBound(r.bounds, got), 1e-5);
  EXPECT_GT(test::signedVolume(mesh.positions, mesh.triangles), 0.0); // counter-clockwise seen from outside
  EXPECT_NE(r.report(o).find("bunny.obj"), std::string::npos);

  // Isovalue h: the surface grown by one voxel, so each bound moves out by about h.
  o.isovalue = h;
  o.output = dir / "grown.obj";
  const Bounds grown = meshLevelSet(o).bounds;
  EXPECT_NEAR(grown.max.x - got.max.x, h, 0.5 * h);
  EXPECT_NEAR(got.min.y - grown.min.y, h, 0.5 * h);
}

TEST(MeshJob, WritesObjPlyAndStlWithTheSameTriangles) {
  TempDir dir;
  writeBake(bunnyBake(), dir / "bunny.vdb");
  MeshOptions o;
  o.input = dir / "bunny.vdb";
  std::uint64_t triangles = 0;
  for (const char* name : {"m.obj", "m.ply", "m.stl", "M.STL"}) {
    o.output = dir / name;
    const MeshResult r = meshLevelSet(o);
    triangles = triangles ? triangles : r.triangles;
    EXPECT_EQ(r.triangles, triangles) << name;
    EXPECT_EQ(loadMeshFile(o.output).triangles.size(), r.triangles) << name;
  }
  o.output = dir / "m.obj";
  o.adaptivity = 0.5; // flat parts merged: fewer triangles, the same place
  const MeshResult fewer = meshLevelSet(o);
  EXPECT_LT(fewer.triangles, triangles);
  EXPECT_LE(farthestBound(fewer.bounds, bunnyBounds()), bunnyBake().spec.voxelSize);
  EXPECT_FALSE(std::filesystem::exists(dir / "m.mtl")); // one file: no material library
}

TEST(MeshJob, AMeshOfAnUpZBakeStandsUprightAsTheBakeDoes) {
  TempDir dir;
  BakeOutputOptions up;
  up.vdb.up = UpAxis::Z;
  writeBake(bunnyBake(), dir / "z.vdb", up);
  MeshOptions o;
  o.input = dir / "z.vdb";
  o.output = dir / "z.obj";
  const MeshResult r = meshLevelSet(o);
  EXPECT_EQ(r.upAxis, "z");
  const Bounds y = bunnyBounds();
  const Bounds turned{{y.min.x, -y.max.z, y.min.y}, {y.max.x, -y.min.z, y.max.y}}; // (x, y, z) -> (x, -z, y)
  const double h = bunnyBake().spec.voxelSize;
  EXPECT_LE(farthestBound(r.bounds, turned), 1.0 * h); // as the Y-up mesh: the ear tips a voxel short at most
  EXPECT_LE(std::fabs(r.bounds.min.x - turned.min.x), 0.5 * h);
  EXPECT_GT(r.bounds.max.z - r.bounds.min.z, r.bounds.max.y - r.bounds.min.y); // the bunny is taller than deep
}

TEST(MeshJob, RefusesBadRequestsWritingNothing) {
  TempDir dir;
  test::writeLevelSetFiles(dir.path());
  writeVdb(dir / "sphere.vdb", {test::sphereLevelSet()});
  auto errorOf = [&](MeshOptions o) -> std::string {
    try {
      meshLevelSet(o);
    } catch (const Error& e) {
      EXPECT_FALSE(std::filesystem::exists(o.output)) << o.output;
      return e.what();
    }
    return "";
  };
  MeshOptions o;
  o.input = dir / "sphere.vdb";
  o.output = dir / "out.txt";
  EXPECT_NE(errorOf(o).find("out.txt: a mesh is written as .obj, .ply or .stl"), std::string::npos);
  o.output = dir / "out.obj";
  o.adaptivity = 2.0;
  EXPECT_THROW(meshLevelSet(o), SettingError);
  o.adaptivity = 0.0;
  o.isovalue = NAN;
  EXPECT_THROW(meshLevelSet(o), SettingError);
  o.isovalue = 5.0; // beyond the band: no voxel crosses it
  EXPECT_NE(errorOf(o).find("crosses no voxel"), std::string::npos);
  o.isovalue = 0.0;
  o.input = dir / "fog.vdb";
  EXPECT_NE(errorOf(o).find("fog volume, not a level set"), std::string::npos);
  o.input = dir / "two.vdb";
  EXPECT_THROW(meshLevelSet(o), SettingError);
  o.grid = "left";
  EXPECT_GT(meshLevelSet(o).triangles, 100u);
}
