#include "TestUtil.h"
#include "grid/VdbIO.h"
#include "util/AtomicFile.h"
#include "util/Error.h"

#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::runCommand;
using rtsdf::test::sphereField;

TEST(VdbIO, DenseToLevelSetKeepsTheBandAndSigns) {
  const GridSpec g = GridSpec::fromBounds({{-1, -0.6, -0.8}, {1, 0.6, 0.8}}, 37, 0.1);
  const std::vector<float> dense = sphereField(g, {0.1, 0, 0}, 0.5);
  const float band = 0.15f;
  const auto grid = denseToLevelSet(dense, g, band);
  std::uint64_t inBand = 0;
  for (float v : dense) inBand += std::fabs(v) <= band;
  EXPECT_EQ(grid->activeVoxelCount(), inBand);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_FLOAT_EQ(grid->background(), band);
  // Sampling back: band voxels exact, others ±band with the right sign (signed flood fill).
  const std::vector<float> back = levelSetToDense(*grid, g);
  for (std::size_t i = 0; i < dense.size(); ++i) {
    if (std::fabs(dense[i]) <= band) ASSERT_EQ(back[i], dense[i]) << i;
    else ASSERT_EQ(back[i], std::copysign(band, dense[i])) << i;
  }
  // The world position of voxel (i,j,k) is the cell centre.
  const openvdb::Vec3d w = grid->transform().indexToWorld(openvdb::Coord(3, 4, 5));
  const glm::dvec3 c = g.indexToWorld(glm::dvec3(3, 4, 5));
  EXPECT_NEAR(w.x(), c.x, 1e-12);
  EXPECT_NEAR(w.y(), c.y, 1e-12);
  EXPECT_NEAR(w.z(), c.z, 1e-12);
}

TEST(VdbIO, WriteReadRoundTripKeepsValuesClassTransformAndMetadata) {
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 24, 0.2);
  const std::vector<float> dense = sphereField(g, {0, 0, 0}, 0.6);
  auto grid = denseToLevelSet(dense, g, 0.3f);
  stampLevelSet(*grid, g, {{"method", "test"}, {"band", "0.3"}});
  for (VdbCompression c : {VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::None}) {
    const auto path = dir / "sphere.vdb";
    writeVdb(path, {grid, makeFogGrid(*grid)}, {c, false});
    const auto read = readLevelSet(path);
    EXPECT_EQ(read->getName(), "surface");
    EXPECT_EQ(read->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(read->transform(), grid->transform());
    EXPECT_EQ(read->activeVoxelCount(), grid->activeVoxelCount());
    EXPECT_EQ(read->metaValue<std::string>("rtsdf:method"), "test");
    const GridSpec back = gridSpecOf(*read);
    EXPECT_EQ(back.dims, g.dims);
    EXPECT_DOUBLE_EQ(back.voxelSize, g.voxelSize);
    const std::vector<float> values = levelSetToDense(*read, g), written = levelSetToDense(*grid, g);
    for (std::size_t i = 0; i < values.size(); ++i) ASSERT_EQ(values[i], written[i]) << i;
    const auto all = readVdb(path);
    ASSERT_EQ(all.size(), 2u);
    const auto fog = std::find_if(all.begin(), all.end(), [](const auto& g) { return g->getName() == "density"; });
    ASSERT_NE(fog, all.end());
    EXPECT_EQ((*fog)->getGridClass(), openvdb::GRID_FOG_VOLUME);
  }
}

TEST(VdbIO, HalfFloatsAreSmallerAndClose) {
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 48, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  stampLevelSet(*grid, g, {});
  writeVdb(dir / "full.vdb", {grid}, {VdbCompression::None, false});
  auto copy = grid->deepCopy();
  writeVdb(dir / "half.vdb", {copy}, {VdbCompression::None, true});
  EXPECT_LT(std::filesystem::file_size(dir / "half.vdb"), std::filesystem::file_size(dir / "full.vdb"));
  const auto half = readLevelSet(dir / "half.vdb");
  const auto a = levelSetToDense(*grid, g), b = levelSetToDense(*half, g);
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-3);
}

TEST(VdbIO, FailedWritesLeaveNoFileAndKeepTheOldOne) {
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 8, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  EXPECT_THROW(writeVdb(dir / "no-such-dir" / "x.vdb", {grid}), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "no-such-dir"));
  EXPECT_THROW(writeVdb(dir.path(), {grid}), Error); // a folder, not a file

  // A write that fails midway (after writing part of the file) must leave the old file untouched.
  const auto path = dir / "keep.vdb";
  rtsdf::test::writeText(path, "old");
  openvdb::GridPtrVec bad{grid, nullptr};
  EXPECT_THROW(writeVdb(path, bad), Error);
  EXPECT_THROW(writeFileAtomically(path,
                                   [](const std::filesystem::path& tmp) {
                                     rtsdf::test::writeText(tmp, "partial");
                                     throw Error("disk full");
                                   }),
               Error);
  std::ifstream in(path);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "old");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1u); // no temporary left behind
}

TEST(VdbIO, ReadErrorsNameTheFile) {
  TempDir dir;
  rtsdf::test::writeText(dir / "junk.vdb", "not a vdb");
  for (const auto& p : {dir / "junk.vdb", dir / "missing.vdb"}) {
    try {
      readVdb(p);
      FAIL() << "no error for " << p;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(p.filename().string()), std::string::npos) << e.what();
    }
  }
}

TEST(VdbIO, PythonOpenVdbReadsTheLevelSet) {
  int status = 0;
  // A dependency the project installs (scripts/install-deps.sh): missing, it fails rather than skips.
  const std::string missing = runCommand("/usr/bin/python3 -c 'import pyopenvdb' 2>&1", status);
  ASSERT_EQ(status, 0) << "python3-openvdb (pyopenvdb) is missing for /usr/bin/python3; scripts/install-deps.sh "
                          "installs it: "
                       << missing;
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 20, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  stampLevelSet(*grid, g, {{"method", "test"}});
  const auto path = dir / "py.vdb";
  writeVdb(path, {grid});
  const std::string out = runCommand("/usr/bin/python3 -c \"import pyopenvdb as vdb; g = vdb.read('" + path.string() +
                                  "', 'surface'); print(g.gridClass, g.transform.voxelSize()[0], g.activeVoxelCount(), "
                                  "g.background, g['rtsdf:method'], sep='|')\"",
                              status);
  ASSERT_EQ(status, 0) << out;
  std::vector<std::string> f;
  std::stringstream ss(out.substr(0, out.find('\n')));
  for (std::string item; std::getline(ss, item, '|');) f.push_back(item);
  ASSERT_EQ(f.size(), 5u) << out;
  EXPECT_EQ(f[0], "level set") << out;
  EXPECT_NEAR(std::stod(f[1]), g.voxelSize, 1e-9);
  EXPECT_EQ(std::stoull(f[2]), grid->activeVoxelCount());
  EXPECT_NEAR(std::stod(f[3]), 0.3, 1e-6);
  EXPECT_EQ(f[4], "test");
}

namespace {

/// A small level-set sphere written by rtsdf's writer (with grid offsets) and by an OpenVDB stream (without).
std::pair<std::string, std::string> sphereFileBytes(const std::filesystem::path& dir) {
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 16, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  stampLevelSet(*grid, g, {{"method", "test"}});
  writeVdb(dir / "s.vdb", {grid});
  std::ifstream in(dir / "s.vdb", std::ios::binary);
  std::ostringstream stream;
  openvdb::io::Stream(stream).write({grid});
  return {std::string(std::istreambuf_iterator<char>(in), {}), stream.str()};
}

} // namespace

// The defensive reader takes both layouts, and refuses every cut of a file with one short line naming it.
TEST(VdbIO, DefensiveReaderTakesBothLayoutsAndRefusesEveryTruncation) {
  TempDir dir;
  const auto [file, stream] = sphereFileBytes(dir.path());
  for (const std::string* bytes : {&file, &stream}) {
    const openvdb::GridPtrVec grids = readVdbBytes(*bytes, "whole.vdb");
    ASSERT_EQ(grids.size(), 1u);
    EXPECT_GT(grids[0]->activeVoxelCount(), 1000u);
    int refused = 0;
    for (std::size_t cut = 0; cut < bytes->size(); cut += 1 + cut / 16) {
      try {
        readVdbBytes(bytes->substr(0, cut), "cut.vdb");
        ADD_FAILURE() << "a cut at " << cut << " of " << bytes->size() << " bytes was read";
      } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind("cut.vdb: not a readable .vdb file: ", 0), 0u) << m;
        EXPECT_LT(m.size(), 300u) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        ++refused;
      }
    }
    EXPECT_GT(refused, 50);
  }
}

// Numbers in rtsdf:* metadata are numbers; files that stored them as text still read.
TEST(VdbIO, MetadataNumbersAreStoredAsNumbersAndOldTextNumbersStillRead) {
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 16, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  stampLevelSet(*grid, g, {{"method", "test"}, {"band", 0.3}, {"resolution", 16}, {"seed", std::int64_t(1) << 40},
                           {"old", "0.25"}, {"word", "abc"}});
  EXPECT_EQ(grid->metaValue<double>("rtsdf:band"), 0.3);
  EXPECT_EQ(grid->metaValue<int>("rtsdf:resolution"), 16);
  EXPECT_EQ(grid->metaValue<std::int64_t>("rtsdf:seed"), std::int64_t(1) << 40);
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:method"), "test");
  EXPECT_EQ(numberMeta(*grid, "rtsdf:band").value_or(-1.0), 0.3);
  EXPECT_EQ(numberMeta(*grid, "rtsdf:resolution").value_or(-1.0), 16.0);
  EXPECT_EQ(numberMeta(*grid, "rtsdf:old").value_or(-1.0), 0.25); // text, as files of older versions hold it
  EXPECT_FALSE(numberMeta(*grid, "rtsdf:word").has_value());
  EXPECT_FALSE(numberMeta(*grid, "rtsdf:missing").has_value());
  EXPECT_EQ(stringMeta(*grid, "rtsdf:resolution"), "16");
}

// --up z: the transform turned (x, y, z) -> (x, -z, y), recorded, undone exactly by inSceneFrame; the caller's grid
// is left as it was.
TEST(VdbIO, UpZTurnsTheWrittenTransformAndReadersTurnItBack) {
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-0.5, 0.0, -0.3}, {0.7, 1.1, 0.4}}, 24, 0.1);
  auto grid = denseToLevelSet(sphereField(g, {0.1, 0.5, 0.05}, 0.3), g, 0.15f);
  stampLevelSet(*grid, g, {{"method", "test"}});
  const openvdb::math::Transform before = grid->transform();
  VdbWriteOptions o;
  o.up = UpAxis::Z;
  writeVdb(dir / "z.vdb", {grid}, o);
  EXPECT_EQ(grid->transform(), before);
  EXPECT_EQ(upAxisOf(*grid), UpAxis::Y);
  const auto z = readLevelSet(dir / "z.vdb");
  EXPECT_EQ(upAxisOf(*z), UpAxis::Z);
  EXPECT_EQ(z->metaValue<std::string>("rtsdf:up"), "z");
  const openvdb::Coord ijk(3, 17, 9);
  const openvdb::Vec3d yUp = before.indexToWorld(ijk), zUp = z->transform().indexToWorld(ijk);
  EXPECT_LT((zUp - openvdb::Vec3d(yUp.x(), -yUp.z(), yUp.y())).length(), 1e-12);
  EXPECT_TRUE(z->hasUniformVoxels());
  EXPECT_NEAR(z->voxelSize()[0], g.voxelSize, 1e-12);
  const GridSpec back = gridSpecOf(*z); // checked against the turned transform
  EXPECT_EQ(back.dims, g.dims);
  const auto scene = inSceneFrame(z);
  EXPECT_EQ(scene->transform(), *makeTransform(g));
  EXPECT_EQ(upAxisOf(*scene), UpAxis::Y);
  EXPECT_EQ(z->transform().indexToWorld(ijk), zUp); // the file's grid is not changed by inSceneFrame
  auto odd = grid->deepCopy();
  odd->insertMeta("rtsdf:up", openvdb::StringMetadata("x"));
  EXPECT_THROW(upAxisOf(*odd), Error);
}

// A grid that records an absolute scene also records it relative to the file's folder.
TEST(VdbIO, WritingAGridThatRecordsItsSceneAddsThePathRelativeToTheFile) {
  TempDir dir;
  std::filesystem::create_directories(dir / "out");
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 16, 0.2);
  auto grid = denseToLevelSet(sphereField(g, {0, 0, 0}, 0.6), g, 0.3f);
  stampLevelSet(*grid, g, {{"scene", (dir / "scenes" / "s.json").string()}});
  writeVdb(dir / "out" / "a.vdb", {grid});
  const auto read = readLevelSet(dir / "out" / "a.vdb");
  EXPECT_EQ(read->metaValue<std::string>("rtsdf:scene"), (dir / "scenes" / "s.json").string());
  EXPECT_EQ(read->metaValue<std::string>("rtsdf:scene_relative"), "../scenes/s.json");
  EXPECT_FALSE((*grid)["rtsdf:scene_relative"]); // the caller's grid is left as it was
}
