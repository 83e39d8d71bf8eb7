// The walk of a .vdb's bytes before OpenVDB reads them (grid/VdbLayout.h): every file OpenVDB writes for the grid
// types rtsdf reads still reads, exactly as plain OpenVDB reads it; crafted files are refused with the file named.
#include "TestUtil.h"
#include "grid/VdbIO.h"
#include "util/Error.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/points/PointDataGrid.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>

using namespace rtsdf;
using rtsdf::test::TempDir;

namespace {

std::string fileBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// @a grids as OpenVDB writes them: through io::File (grid offsets) or io::Stream (none).
std::string written(const openvdb::GridPtrVec& grids, std::uint32_t compression, bool half, bool offsets) {
  openvdb::initialize();
  for (const auto& g : grids) g->setSaveFloatAsHalf(half);
  if (!offsets) {
    std::ostringstream os;
    openvdb::io::Stream stream(os);
    stream.setCompression(compression);
    stream.write(grids);
    return os.str();
  }
  TempDir dir;
  openvdb::io::File file((dir / "g.vdb").string());
  file.setCompression(compression);
  file.write(grids);
  file.close();
  return fileBytes(dir / "g.vdb");
}

/// Grids as a canonical byte string (uncompressed, without the header's random UUID): equal strings, equal grids.
std::string canonical(const openvdb::GridPtrVec& grids) {
  std::ostringstream os;
  openvdb::io::Stream stream(os);
  stream.setCompression(openvdb::io::COMPRESS_NONE);
  stream.write(grids);
  return os.str().substr(57);
}

/// Where two canonical strings first differ (npos when equal): a message, not megabytes of bytes.
std::size_t firstDifference(const std::string& a, const std::string& b) {
  if (a == b) return std::string::npos;
  const auto d = std::mismatch(a.begin(), a.begin() + std::min(a.size(), b.size()), b.begin());
  return std::size_t(d.first - a.begin());
}

openvdb::GridPtrVec plainOpenVdb(const std::string& bytes) {
  openvdb::initialize(); // a test may read plainly before readVdbBytes registered the grid types
  std::istringstream in(bytes);
  return *openvdb::io::Stream(in, /*delayLoad=*/false).getGrids(); // as readVdbBytes reads
}

std::string refusal(const std::string& bytes, const std::string& name = "crafted.vdb") {
  try {
    readVdbBytes(bytes, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "(read without an error)";
}

/// The grids rtsdf and level-set tools write, one file of each kind: a level set, a fog volume, a vec3 grid
/// beside it, tiles, and grids of every value type the reader takes.
openvdb::GridPtrVec everyKindOfGrid() {
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(0.1f, 0, 0), 0.05f);
  sphere->setName("surface");
  auto fog = sphere->deepCopy();
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->tree().fill(openvdb::CoordBBox({-40, -40, -40}, {-9, -9, -9}), 0.5f, true); // active tiles and leaves
  fog->tree().addTile(3, openvdb::Coord(8192, 0, 0), 0.25f, true);                   // a root tile
  auto velocity = openvdb::Vec3SGrid::create(openvdb::Vec3s(0));
  velocity->setName("v");
  auto vec3d = openvdb::Vec3DGrid::create(openvdb::Vec3d(1, 2, 3));
  auto vec3i = openvdb::Vec3IGrid::create();
  auto doubles = openvdb::DoubleGrid::create(-1.0);
  auto int32s = openvdb::Int32Grid::create(7);
  auto int64s = openvdb::Int64Grid::create();
  auto bools = openvdb::BoolGrid::create(false);
  auto mask = openvdb::MaskGrid::create();
  int i = 0;
  for (auto it = sphere->cbeginValueOn(); it; ++it, ++i) {
    if (i % 3) continue;
    const openvdb::Coord c = it.getCoord();
    velocity->tree().setValue(c, openvdb::Vec3s(float(c.x()), float(i), 0.5f));
    vec3d->tree().setValue(c, openvdb::Vec3d(c.y(), 0.25, -i));
    vec3i->tree().setValue(c, openvdb::Vec3i(c.x(), c.y(), c.z()));
    doubles->tree().setValue(c, 1.0 / (1 + i));
    int32s->tree().setValue(c, -i);
    int64s->tree().setValue(c, std::int64_t(i) << 33);
    bools->tree().setValue(c, i % 2 == 0);
    mask->tree().setValueOn(c);
  }
  vec3d->setTransform(openvdb::math::Transform::createLinearTransform(0.25)); // other map types
  doubles->transform().postRotate(0.3, openvdb::math::Y_AXIS);
  return {sphere, fog, velocity, vec3d, vec3i, doubles, int32s, int64s, bools, mask};
}

/// The offset of the stated size of the first blosc chunk holding @a bytes bytes (found by its header).
std::size_t bloscChunk(const std::string& file, std::uint32_t bytes) {
  for (std::size_t p = 8; p + 16 <= file.size(); ++p) {
    std::int64_t stated;
    std::uint32_t n, cbytes;
    std::memcpy(&stated, file.data() + p - 8, 8);
    std::memcpy(&n, file.data() + p + 4, 4);
    std::memcpy(&cbytes, file.data() + p + 12, 4);
    if (file[p] == 2 && n == bytes && stated == cbytes) return p - 8;
  }
  ADD_FAILURE() << "no blosc chunk of " << bytes << " bytes";
  return 0;
}

template <class T> void put(std::string& file, std::size_t at, T value) { std::memcpy(&file[at], &value, sizeof value); }

/// The offset of the first grid's three offsets (gridPos, blockPos, endPos) in a file with one grid.
std::size_t descriptorOffsets(const std::string& file) {
  std::size_t p = 57 + 4 + 4; // header, empty file metadata, grid count
  for (int s = 0; s < 3; ++s) {
    std::uint32_t n;
    std::memcpy(&n, file.data() + p, 4);
    p += 4 + n;
  }
  return p;
}

/// A grid with one dense leaf of 512 random bit patterns: neither zip nor blosc can shrink its chunk.
openvdb::FloatGrid::Ptr oneLeaf() {
  auto grid = openvdb::FloatGrid::create(0.123456f);
  grid->setName("surface");
  std::uint32_t state = 12345;
  for (int i = 0; i < 512; ++i) {
    state = state * 1664525u + 1013904223u;
    float v;
    std::memcpy(&v, &state, sizeof v);
    grid->tree().setValue(openvdb::Coord(i >> 6, (i >> 3) & 7, i & 7), v);
  }
  return grid;
}

} // namespace

// Every compression, half floats, with and without offsets, every grid type the reader takes: read as plain
// OpenVDB reads them.
TEST(VdbLayout, EveryFileOpenVdbWritesReadsAsPlainOpenVdbReadsIt) {
  openvdb::initialize();
  const openvdb::GridPtrVec grids = everyKindOfGrid();
  namespace io = openvdb::io;
  const std::vector<std::uint32_t> compressions{io::COMPRESS_NONE, io::COMPRESS_ACTIVE_MASK,
                                                io::COMPRESS_ZIP | io::COMPRESS_ACTIVE_MASK,
                                                io::COMPRESS_BLOSC | io::COMPRESS_ACTIVE_MASK, io::COMPRESS_BLOSC,
                                                io::COMPRESS_ZIP};
  for (const std::uint32_t c : compressions)
    for (const bool half : {false, true})
      for (const bool offsets : {true, false}) {
        const std::string bytes = written(grids, c, half, offsets);
        SCOPED_TRACE(testing::Message() << "compression " << c << (half ? ", half" : "") << (offsets ? ", file" : ""));
        openvdb::GridPtrVec read;
        ASSERT_NO_THROW(read = readVdbBytes(bytes, "every.vdb"));
        ASSERT_EQ(read.size(), grids.size());
        const std::string a = canonical(read), b = canonical(plainOpenVdb(bytes));
        const std::size_t d = firstDifference(a, b);
        EXPECT_EQ(d, std::string::npos) << testing::PrintToString(a.substr(d > 20 ? d - 20 : 0, 60)) << " vs "
                                        << testing::PrintToString(b.substr(d > 20 ? d - 20 : 0, 60));
        for (std::size_t i = 0; i < grids.size(); ++i) EXPECT_EQ(read[i]->type(), grids[i]->type());
      }
  for (const auto& g : grids) g->setSaveFloatAsHalf(false);
  EXPECT_EQ(firstDifference(canonical(readVdbBytes(written(grids, io::COMPRESS_NONE, false, true), "every.vdb")),
                            canonical(grids)),
            std::string::npos);
}

// A grid that shares its tree with another is written as an instance (no tree of its own).
TEST(VdbLayout, InstancesRead) {
  openvdb::initialize();
  auto a = oneLeaf();
  auto b = a->copyGrid();
  b->setName("copy");
  const openvdb::GridPtrVec read = readVdbBytes(written({a, b}, openvdb::io::COMPRESS_BLOSC, false, true), "i.vdb");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1]->activeVoxelCount(), 512u);
}

// The files `rtsdf bake` wrote of the bunny (blosc; zip with half floats): read as plain OpenVDB reads them.
TEST(VdbLayout, BakeOutputsRead) {
  for (const char* name : {"bunny-blosc.vdb", "bunny-zip-half.vdb"}) {
    const std::string bytes = fileBytes(std::string(RTSDF_DATA_DIR) + "/../fuzz/seeds/fuzz_vdb/" + name);
    ASSERT_GT(bytes.size(), 10000u) << name;
    EXPECT_EQ(firstDifference(canonical(readVdbBytes(bytes, name)), canonical(plainOpenVdb(bytes))), std::string::npos)
        << name;
  }
}

// The fuzzer's finding: a chunk stated as uncompressed and longer than its leaf's buffer, which OpenVDB 10 reads
// into the buffer before it compares the lengths. Crafted the same way for blosc and zip, and the walk refuses.
TEST(VdbLayout, UncompressedChunkLongerThanItsBufferIsRefused) {
  const std::string finding =
      fileBytes(std::string(RTSDF_DATA_DIR) + "/../fuzz/regressions/fuzz_vdb/uncompressed-chunk-longer-than-its-buffer.vdb");
  ASSERT_GT(finding.size(), 1000u);
  const std::string m = refusal(finding, "finding.vdb");
  EXPECT_EQ(m.rfind("finding.vdb: not a readable .vdb file: ", 0), 0u) << m;
  EXPECT_NE(m.find("uncompressed bytes where"), std::string::npos) << m;

  std::string blosc = written({oneLeaf()}, openvdb::io::COMPRESS_BLOSC, false, true);
  put<std::int64_t>(blosc, bloscChunk(blosc, 2048), -4096);
  EXPECT_NE(refusal(blosc).find("a blosc chunk of values states 4096 uncompressed bytes where 2048 are expected"),
            std::string::npos) << refusal(blosc);
  // zip: the leaf's chunk is the last thing in the file.
  std::string zip = written({oneLeaf()}, openvdb::io::COMPRESS_ZIP, false, false);
  std::string longer = zip;
  const std::size_t at = zip.size() - 2048 - 8;
  put<std::int64_t>(zip, at, -4096);
  EXPECT_NE(refusal(zip).find("a zip chunk of values states 4096 uncompressed bytes"), std::string::npos)
      << refusal(zip);
  put<std::int64_t>(longer, at, -2048);
  EXPECT_NO_THROW(readVdbBytes(longer, "z.vdb")); // the same file as written
}

// A compressed chunk whose stated size runs past the grid's end, or that its blosc header contradicts.
TEST(VdbLayout, CompressedChunkPastTheGridsEndIsRefused) {
  std::string file = written({oneLeaf()}, openvdb::io::COMPRESS_BLOSC, false, true);
  const std::size_t at = bloscChunk(file, 2048);
  std::string past = file;
  put<std::int64_t>(past, at, std::int64_t(file.size()));
  EXPECT_NE(refusal(past).find("past the grid's end"), std::string::npos) << refusal(past);
  std::string header = file;
  put<std::uint32_t>(header, at + 8 + 4, 4096); // the blosc header's uncompressed size
  EXPECT_NE(refusal(header).find("whose header says 4096 bytes"), std::string::npos) << refusal(header);
}

// Counts and offsets that the file cannot hold: root children, a grid whose walk does not end at its end offset.
TEST(VdbLayout, TopologyAndOffsetsThatDoNotFitAreRefused) {
  const std::string file = written({oneLeaf()}, openvdb::io::COMPRESS_BLOSC, false, true);
  const float background = 0.123456f;
  const std::size_t root = file.find(std::string(reinterpret_cast<const char*>(&background), 4)) + 4;
  ASSERT_GT(root, 100u);
  std::string children = file;
  put<std::uint32_t>(children, root + 4, 1000); // the root's child count (after its tile count)
  EXPECT_NE(refusal(children).find("1000 root children cannot fit"), std::string::npos) << refusal(children);
  std::string tile = file;
  put<std::uint32_t>(tile, root, 1);
  EXPECT_NE(refusal(tile).find("crafted.vdb: not a readable .vdb file: grid 0 ('surface' of type Tree_float_5_4_3)"),
            std::string::npos) << refusal(tile);

  // Four bytes more at the end, and an end offset that takes them in: the grid's data ends before its offset.
  std::string longer = file + "abcd";
  const std::size_t offsets = descriptorOffsets(longer);
  put<std::int64_t>(longer, offsets + 16, std::int64_t(longer.size()));
  EXPECT_NO_THROW(plainOpenVdb(longer)); // OpenVDB's Stream ignores offsets
  EXPECT_NE(refusal(longer).find("not at its end offset " + std::to_string(longer.size())), std::string::npos)
      << refusal(longer);
  std::string block = file;
  put<std::int64_t>(block, offsets + 8, 0);
  EXPECT_NE(refusal(block).find("not at its block offset 0"), std::string::npos) << refusal(block);
}

// Grids of other types (points here) are refused before OpenVDB reads them, naming the file, grid and type.
TEST(VdbLayout, OtherGridTypesAreRefused) {
  openvdb::initialize();
  // An empty grid is enough: the refusal reads the grid's type from its descriptor, before any node.
  auto points = openvdb::points::PointDataGrid::create();
  points->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
  points->setName("points");
  const std::string file = written({oneLeaf(), points}, openvdb::io::COMPRESS_BLOSC, false, true);
  EXPECT_EQ(plainOpenVdb(file).size(), 2u);
  const std::string m = refusal(file, "p.vdb");
  EXPECT_EQ(m.rfind("p.vdb: not a readable .vdb file: grid 1 ('points' of type Tree_ptdataidx32", 0), 0u) << m;
  EXPECT_NE(m.find("rtsdf reads grids of float, double, int32, int64, vec3s, vec3d, vec3i, bool and mask values only"),
            std::string::npos) << m;
  EXPECT_LT(m.size(), 300u);
}

// OpenVDB reads half floats when the grid's is_saved_as_half_float metadata says so, whatever the descriptor's
// "_HalfFloat" type suffix says (the fuzzer's input: the walk had trusted the suffix and let a chunk through).
TEST(VdbLayout, HalfFloatsFollowTheGridsMetadataNotTheTypeName) {
  openvdb::initialize();
  const std::string half = written({oneLeaf()}, openvdb::io::COMPRESS_BLOSC, true, false);
  const std::string suffixed = "Tree_float_5_4_3_HalfFloat";
  const std::size_t at = half.find(suffixed);
  ASSERT_NE(at, std::string::npos);
  std::string unsuffixed = half.substr(0, at - 4);
  const std::uint32_t length = 16;
  unsuffixed += std::string(reinterpret_cast<const char*>(&length), 4) + "Tree_float_5_4_3" + half.substr(at + 26);
  for (const std::string* bytes : {&half, static_cast<const std::string*>(&unsuffixed)}) {
    openvdb::GridPtrVec read;
    ASSERT_NO_THROW(read = readVdbBytes(*bytes, "h.vdb"));
    EXPECT_EQ(firstDifference(canonical(read), canonical(plainOpenVdb(*bytes))), std::string::npos);
    EXPECT_TRUE(read.front()->saveFloatAsHalf());
  }
  const std::string finding = fileBytes(std::string(RTSDF_DATA_DIR) +
                                        "/../fuzz/regressions/fuzz_vdb/half-float-flag-in-metadata-not-in-the-type-name.vdb");
  ASSERT_GT(finding.size(), 1000u);
  EXPECT_EQ(refusal(finding, "f.vdb").rfind("f.vdb: not a readable .vdb file: ", 0), 0u) << refusal(finding, "f.vdb");
}

// fuzz_compare's input: a file whose scale-translate map is singular reads in plain OpenVDB, which throws only
// when the transform is copied (ending the process there); readVdbBytes refuses it.
TEST(VdbLayout, SingularMapsAreRefused) {
  const std::string pair = fileBytes(std::string(RTSDF_DATA_DIR) +
                                     "/../fuzz/regressions/fuzz_compare/singular-scale-translate-map-ended-the-process");
  ASSERT_GT(pair.size(), 4u);
  std::uint32_t split;
  std::memcpy(&split, pair.data(), 4);
  const std::string rest = pair.substr(4);
  const std::size_t first = split % (rest.size() + 1); // as fuzz/fuzz_compare.cpp splits it
  int singular = 0;
  for (const std::string& part : {rest.substr(0, first), rest.substr(first)}) {
    openvdb::GridPtrVec plain;
    try {
      plain = plainOpenVdb(part);
    } catch (const std::exception&) {
      continue;
    }
    bool broken = false;
    for (const auto& g : plain) {
      try {
        (void)g->transform().baseMap()->getAffineMap();
      } catch (const openvdb::ArithmeticError&) {
        broken = true;
      }
    }
    if (!broken) continue;
    ++singular;
    EXPECT_EQ(refusal(part, "s.vdb").rfind("s.vdb: not a readable .vdb file: ", 0), 0u) << refusal(part, "s.vdb");
  }
  EXPECT_EQ(singular, 1);
}
