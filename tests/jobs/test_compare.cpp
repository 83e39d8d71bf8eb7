// compare: two level sets of the same space in A's voxels, whatever their transforms (our own files, shifted or
// resampled ones, a file written by pyopenvdb), or one file against an anchor baked on its own voxels; the
// errors that remain (no active voxel, no overlap); and the voxels an rtsdf bake shares with an exact one.
#include "TestUtil.h"
#include "LevelSetFiles.h"
#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/Compare.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::runCommand;
using rtsdf::test::sphereField;

namespace {

/// A sphere of radius 0.5 at @a centre as an rtsdf level set file on @a g with a band of @a band.
void writeSphere(const std::filesystem::path& path, const GridSpec& g, const glm::dvec3& centre, float band) {
  auto grid = denseToLevelSet(sphereField(g, centre, 0.5), g, band);
  stampLevelSet(*grid, g, {{"method", "test"}});
  writeVdb(path, {grid});
}

GridSpec cube(double h, double shiftInVoxels) {
  GridSpec g = GridSpec::fromBounds({{-0.7, -0.7, -0.7}, {0.7, 0.7, 0.7}}, int(std::lround(1.4 / h)), 0.1);
  g.origin += shiftInVoxels * g.voxelSize;
  return g;
}

/// Voxels of @a path's level set within @a voxels voxels of zero: the only ones where an interpolation error of
/// that size can flip a sign.
std::uint64_t nearZero(const std::filesystem::path& path, double voxels) {
  const auto g = readLevelSet(path);
  std::uint64_t n = 0;
  for (auto it = g->cbeginValueOn(); it; ++it) n += std::fabs(*it) <= voxels * g->voxelSize()[0];
  return n;
}

std::string errorOf(const CompareOptions& o) {
  try {
    compare(o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Compare, ResamplesAFileWhoseVoxelsAreOffsetByAFractionOrOfAnotherSize) {
  TempDir dir;
  const GridSpec a = cube(0.02, 0.0);
  writeSphere(dir / "a.vdb", a, {0.05, 0, 0}, 0.06f);
  struct Case { const char* name; GridSpec spec; glm::dvec3 centre; double expectedMean; };
  // The same sphere (error: trilinear interpolation of a curved field, a few hundredths of a voxel), and a
  // sphere 0.01 larger in radius (every distance 0.01 = half of A's voxel smaller): the comparison sees it.
  for (const Case& c : {Case{"fraction", cube(0.02, 0.37), {0.05, 0, 0}, 0.0},
                        Case{"size", cube(0.03, 0.0), {0.05, 0, 0}, 0.0}}) {
    writeSphere(dir / "b.vdb", c.spec, c.centre, 0.09f);
    const FileComparison same = compareFiles(dir / "a.vdb", dir / "b.vdb");
    EXPECT_NE(same.alignment.find("resampled"), std::string::npos) << c.name << ": " << same.alignment;
    EXPECT_GT(same.error.voxels, 0.9 * double(same.activeA)) << c.name;
    EXPECT_LT(same.error.meanAbs, 0.03) << c.name;
    EXPECT_LE(same.error.signMismatches, nearZero(dir / "a.vdb", same.error.maxAbs)) << c.name;
    EXPECT_NE(same.report().find("resampled"), std::string::npos);

    auto larger = denseToLevelSet(sphereField(c.spec, c.centre, 0.51), c.spec, 0.09f);
    stampLevelSet(*larger, c.spec, {{"method", "test"}});
    writeVdb(dir / "c.vdb", {larger});
    const FileComparison off = compareFiles(dir / "a.vdb", dir / "c.vdb");
    EXPECT_NEAR(off.error.meanAbs, 0.5, 0.03) << c.name;
  }
}

TEST(Compare, ReadsALevelSetWrittenByPyopenvdb) {
  int status = 0;
  const std::string version = runCommand("/usr/bin/python3 -c 'import pyopenvdb' 2>&1", status);
  ASSERT_EQ(status, 0) << "python3-openvdb (scripts/install-deps.sh installs it) is missing: " << version;
  TempDir dir;
  // OpenVDB's own sphere: voxel size 0.03, voxel (0,0,0) centred on the origin (not cell-centred like ours).
  const std::string py = "import pyopenvdb as vdb; g = vdb.createLevelSetSphere(radius=0.5, center=(0.05, 0, 0), "
                         "voxelSize=0.03, halfWidth=3.0); vdb.write('" + (dir / "py.vdb").string() + "', grids=[g])";
  const std::string out = runCommand("/usr/bin/python3 -c \"" + py + "\" 2>&1", status);
  ASSERT_EQ(status, 0) << out;
  writeSphere(dir / "ours.vdb", cube(0.02, 0.0), {0.05, 0, 0}, 0.06f);
  for (const auto& [a, b] : {std::pair{"ours.vdb", "py.vdb"}, std::pair{"py.vdb", "ours.vdb"}}) {
    const FileComparison c = compareFiles(dir / a, dir / b);
    EXPECT_FALSE(c.alignment.empty()) << a;
    EXPECT_GT(c.error.voxels, 1000u) << a;
    EXPECT_LT(c.error.meanAbs, 0.05) << a << "\n" << c.report();
    EXPECT_LE(c.error.signMismatches, nearZero(dir / a, c.error.maxAbs)) << a << "\n" << c.report();
  }
}

TEST(Compare, RefusesEmptyLevelSetsAndLevelSetsThatDoNotOverlap) {
  TempDir dir;
  writeSphere(dir / "a.vdb", cube(0.02, 0.0), {0, 0, 0}, 0.06f);
  GridSpec far = cube(0.02, 0.0);
  far.origin += glm::dvec3(10.0, 0.0, 0.0);
  writeSphere(dir / "far.vdb", far, {10, 0, 0}, 0.06f);
  CompareOptions o;
  o.a = dir / "a.vdb";
  o.b = dir / "far.vdb";
  std::string e = errorOf(o);
  EXPECT_NE(e.find("do not overlap"), std::string::npos) << e;
  EXPECT_NE(e.find("far.vdb"), std::string::npos) << e;

  // A sphere too small for the band to hold a voxel centre: a level set with no active voxel.
  const GridSpec g = cube(0.02, 0.0);
  auto empty = denseToLevelSet(sphereField(g, {0, 0, 0}, 5.0), g, 0.01f);
  stampLevelSet(*empty, g, {});
  writeVdb(dir / "empty.vdb", {empty});
  o.b = dir / "empty.vdb";
  e = errorOf(o);
  EXPECT_NE(e.find("empty.vdb: the level set has no active voxels"), std::string::npos) << e;

  o.b.clear();
  EXPECT_THROW(compare(o), SettingError); // neither B nor an anchor
  o.a = dir / "empty.vdb";
  o.against = CompareAnchor::Exact;
  o.scene = test::dataPath("meshes/bunny.obj");
  e = errorOf(o);
  EXPECT_NE(e.find("empty.vdb: the level set has no active voxels"), std::string::npos) << e;
}

TEST(Compare, AgainstAnAnchorBakedOnTheFilesOwnVoxels) {
  TempDir dir;
  BakeOptions bo;
  bo.scene = test::dataPath("scenes/default.json");
  bo.resolution = 40;
  bo.method = BakeMethod::OpenVdb;
  writeBake(bake(bo), dir / "vdb.vdb");
  bo.method = BakeMethod::Exact;
  writeBake(bake(bo), dir / "exact.vdb");
  const FileComparison files = compareFiles(dir / "vdb.vdb", dir / "exact.vdb");
  CompareOptions o;
  o.a = dir / "vdb.vdb";
  o.against = CompareAnchor::Exact; // the scene comes from vdb.vdb's metadata
  const FileComparison anchored = compare(o);
  EXPECT_TRUE(anchored.alignment.empty()) << anchored.alignment;
  EXPECT_EQ(anchored.error.voxels, files.error.voxels);
  EXPECT_EQ(anchored.error.meanAbs, files.error.meanAbs);
  EXPECT_EQ(anchored.error.maxAbs, files.error.maxAbs);
  EXPECT_EQ(anchored.error.signMismatches, files.error.signMismatches);
  EXPECT_GT(anchored.error.meanAbs, 0.0); // OpenVDB's field is not the exact one
  EXPECT_NE(anchored.nameB.find("exact bake"), std::string::npos) << anchored.nameB;
}

TEST(Compare, AgainstAnAnchorForAFileFromAnotherToolGivenItsScene) {
  TempDir dir;
  BakeOptions bo;
  bo.scene = test::dataPath("meshes/bunny.obj");
  bo.resolution = 32;
  bo.pipeline.band = 0.9; // three voxels of the bunny's (its units are ten times the default scene's)
  const BakeResult exact = bake(bo);
  // The same grid without rtsdf's metadata, as another tool would write it: only a transform and a band.
  auto foreign = openvdb::FloatGrid::create(exact.grid->background());
  foreign->setTree(exact.grid->tree().copy());
  foreign->setTransform(exact.grid->transform().copy());
  foreign->setGridClass(openvdb::GRID_LEVEL_SET);
  writeVdb(dir / "foreign.vdb", {foreign});
  CompareOptions o;
  o.a = dir / "foreign.vdb";
  o.against = CompareAnchor::Exact;
  EXPECT_THROW(compare(o), SettingError); // it records no scene
  o.scene = bo.scene;
  const FileComparison c = compare(o);
  EXPECT_GT(exact.grid->activeVoxelCount(), 2000u);
  EXPECT_EQ(c.error.voxels, exact.grid->activeVoxelCount());
  EXPECT_LT(c.error.maxAbs, 1e-4);
  EXPECT_EQ(c.error.signMismatches, 0u);
}

TEST(Compare, AnRtsdfBakeAndAnExactBakeAtTheSameResolutionShareTheirVoxels) {
  for (const char* scene : {"scenes/default.json", "meshes/bunny.obj", "meshes/teapot.obj"}) {
    BakeOptions bo;
    bo.scene = test::dataPath(scene);
    bo.resolution = 96;
    bo.pipeline.coarseRes = 40; // not a divisor of the fine resolution
    bo.pipeline.fineRes = 96;
    const SceneGeometry geo = buildSceneGeometry(loadScene(bo.scene), 0.0);
    const GridSpec fine = pipelineGrids(geo.bounds, bo.pipeline).second;
    const BakeResult exact = bake(bo);
    EXPECT_EQ(exact.spec.dims, fine.dims) << scene;
    EXPECT_EQ(exact.spec.origin, fine.origin) << scene;
    EXPECT_EQ(exact.spec.voxelSize, fine.voxelSize) << scene;
    EXPECT_EQ(*makeTransform(fine), exact.grid->transform()) << scene;
  }
}

// What compare reads is checked: each file that is not a float level set of cubic voxels with finite values is
// refused naming the file, the grid and what is wrong.
TEST(Compare, RefusesGridsThatAreNotFiniteFloatLevelSetsOfCubicVoxels) {
  TempDir dir;
  test::writeLevelSetFiles(dir.path());
  writeVdb(dir / "sphere.vdb", {test::sphereLevelSet()});
  const std::pair<const char*, const char*> cases[] = {
      {"fog.vdb", "grid 'surface' is a fog volume, not a level set"},
      {"double.vdb", "grid 'surface' holds double values"},
      {"nonuniform.vdb", "voxels of 0.03125 x 0.03125 x 0.0625, not cubes"},
      {"frustum.vdb", "has a frustum transform, not a linear one"},
      {"nan.vdb", "holds 1 values that are NaN or infinite"}};
  for (const auto& [file, why] : cases)
    for (const bool asA : {true, false}) {
      CompareOptions o;
      o.a = dir / (asA ? file : "sphere.vdb");
      o.b = dir / (asA ? "sphere.vdb" : file);
      const std::string e = errorOf(o);
      EXPECT_NE(e.find((dir / file).string() + ": grid"), std::string::npos) << e;
      EXPECT_NE(e.find(why), std::string::npos) << e;
    }
  // Each is still what it says, so the refusal is the check's, not the file's.
  EXPECT_EQ(readVdb(dir / "fog.vdb").front()->getGridClass(), openvdb::GRID_FOG_VOLUME);
}

TEST(Compare, SeveralCandidateLevelSetsAreAnErrorListingThemAndGridPicksOne) {
  TempDir dir;
  test::writeLevelSetFiles(dir.path());
  CompareOptions o;
  o.a = o.b = dir / "two.vdb";
  try {
    compare(o);
    ADD_FAILURE() << "two level sets were compared without --grid";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.setting(), "grid");
    const std::string m = e.what();
    EXPECT_NE(m.find("two.vdb holds 2 candidate level sets: 'left' (float level set), 'right' (float level set)"),
              std::string::npos) << m;
  }
  o.grid = "right";
  const FileComparison same = compare(o);
  EXPECT_GT(same.error.voxels, 1000u);
  EXPECT_EQ(same.error.maxAbs, 0.0);
  o.b = dir / "sphere_left.vdb";
  auto left = readLevelSet(dir / "two.vdb", "left");
  left->setName("right"); // the left sphere under the name 'right': --grid reads it, not the first grid
  writeVdb(o.b, {left});
  const FileComparison moved = compare(o); // spheres 0.1 = 3.2 voxels apart in x: |A - B| up to 3.2 voxels
  EXPECT_GT(moved.error.meanAbs, 0.5);
  EXPECT_LE(moved.error.maxAbs, 3.2 + 1e-3);
  o.grid = "middle";
  const std::string e = errorOf(o);
  EXPECT_NE(e.find("two.vdb: no grid named 'middle' (grids: 'left'"), std::string::npos) << e;
}

TEST(Compare, ActiveTilesCountAsTheirVoxels) {
  TempDir dir;
  test::writeLevelSetFiles(dir.path());
  ASSERT_GT(readVdb(dir / "tiles_a.vdb").front()->baseTreePtr()->activeTileCount(), 0u);
  ASSERT_EQ(openvdb::gridPtrCast<openvdb::FloatGrid>(readVdb(dir / "tiles_a.vdb").front())->tree().leafCount(), 0u);
  const FileComparison c = compareFiles(dir / "tiles_a.vdb", dir / "tiles_b.vdb");
  EXPECT_EQ(c.activeA, 4096u);
  EXPECT_EQ(c.error.voxels, 512u); // the 8^3 voxels the two boxes share
  EXPECT_EQ(c.error.onlyInA, 4096u - 512u);
  EXPECT_NEAR(c.error.meanAbs, 0.1, 1e-6);
}

TEST(Compare, WarnsWhenTheFilesLookLikeFieldsOfDifferentScenes) {
  TempDir dir;
  test::writeLevelSetFiles(dir.path());
  const FileComparison scenes = compareFiles(dir / "scene_a.vdb", dir / "scene_b.vdb");
  EXPECT_NE(scenes.warning.find("are fields of different scenes (/scenes/a.obj and /scenes/b.obj)"),
            std::string::npos) << scenes.warning;
  EXPECT_EQ(compareFiles(dir / "scene_a.vdb", dir / "scene_a.vdb").warning, "");
  // No scene recorded: boxes of active voxels that overlap by under half of the smaller one.
  const GridSpec g = GridSpec::fromBounds({{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}}, 96, 0.0);
  writeSphere(dir / "here.vdb", g, {0, 0, 0}, 0.1f);
  writeSphere(dir / "near.vdb", g, {0.2, 0, 0}, 0.1f);
  writeSphere(dir / "far.vdb", g, {0.7, 0, 0}, 0.1f);
  EXPECT_EQ(compareFiles(dir / "here.vdb", dir / "near.vdb").warning, "");
  const FileComparison far = compareFiles(dir / "here.vdb", dir / "far.vdb");
  EXPECT_NE(far.warning.find("may be fields of different scenes: their active voxels' boxes overlap by"),
            std::string::npos) << far.warning;
  EXPECT_EQ(far.report().find("warning"), std::string::npos); // one line, logged; not in the report
}

// A file written with --up z compares with its Y-up twin voxel for voxel: compare reads both in the scene's frame.
TEST(Compare, AFileWrittenUpZComparesWithItsYUpTwinVoxelForVoxel) {
  TempDir dir;
  auto grid = test::sphereLevelSet({0.1, 0.2, 0});
  writeVdb(dir / "y.vdb", {grid});
  VdbWriteOptions up;
  up.up = UpAxis::Z;
  writeVdb(dir / "z.vdb", {grid}, up);
  for (const auto& [a, b] : {std::pair{"y.vdb", "z.vdb"}, std::pair{"z.vdb", "y.vdb"}}) {
    const FileComparison c = compareFiles(dir / a, dir / b);
    EXPECT_EQ(c.alignment, "") << a;
    EXPECT_EQ(c.error.voxels, grid->activeVoxelCount()) << a;
    EXPECT_EQ(c.error.maxAbs, 0.0) << a;
  }
}
