// End-to-end tests of the rtsdf command line: real scenes in, .vdb files out, and every bad input refused
// with a clear message, a non-zero exit and no output file.
#include "TestUtil.h"
#include "grid/VdbIO.h"
#include "image/ImageIO.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::writeText;

namespace {

struct Result {
  int exitCode = -1;
  std::string output; // stdout and stderr together
};

Result rtsdfCmd(const std::string& args) {
  Result r;
  const std::string cmd = std::string(RTSDF_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  const int status = pclose(p);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

/// The number printed right after @a label in @a text (NaN when the label is missing).
double numberAfter(const std::string& text, const std::string& label) {
  const std::size_t at = text.find(label);
  return at == std::string::npos ? NAN : std::strtod(text.c_str() + at + label.size(), nullptr);
}

} // namespace

TEST(Cli, HelpOnEveryCommand) {
  const Result top = rtsdfCmd("--help");
  EXPECT_EQ(top.exitCode, 0);
  for (const char* cmd : {"bake", "info", "compare", "bench", "animate", "render"}) {
    EXPECT_NE(top.output.find(cmd), std::string::npos) << cmd;
    const Result r = rtsdfCmd(std::string(cmd) + " --help");
    EXPECT_EQ(r.exitCode, 0) << cmd;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
  const Result bake = rtsdfCmd("bake --help");
  for (const char* opt : {"--method", "--res", "--band", "--full", "--sign", "--fog", "--half", "--padding"})
    EXPECT_NE(bake.output.find(opt), std::string::npos) << opt;
}

TEST(Cli, BakesTheDefaultSceneWithBothMethodsAndCompares) {
  TempDir dir;
  const std::string scene = q(test::dataPath("scenes/default.json"));
  const Result exact = rtsdfCmd("bake " + scene + " --res 48 --band 0.1 --fog -o " + q(dir / "exact.vdb"));
  ASSERT_EQ(exact.exitCode, 0) << exact.output;
  EXPECT_NE(exact.output.find("active"), std::string::npos);
  const auto grid = readLevelSet(dir / "exact.vdb");
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:method"), "exact");
  EXPECT_EQ(grid->metaValue<int>("rtsdf:resolution"), 48); // numbers are stored as numbers
  EXPECT_GT(grid->activeVoxelCount(), 1000u);
  EXPECT_EQ(readVdb(dir / "exact.vdb").size(), 2u); // surface + density

  const Result vdb = rtsdfCmd("bake " + scene + " --res 48 --band 0.1 --method openvdb -o " + q(dir / "vdb.vdb"));
  ASSERT_EQ(vdb.exitCode, 0) << vdb.output;
  const Result cmp = rtsdfCmd("compare " + q(dir / "exact.vdb") + " " + q(dir / "vdb.vdb"));
  ASSERT_EQ(cmp.exitCode, 0) << cmp.output;
  EXPECT_NE(cmp.output.find("mean"), std::string::npos);
  EXPECT_NE(cmp.output.find("sign"), std::string::npos);

  // Other voxels are resampled, and the report says so; the exact field at 40 is within a few hundredths of a
  // voxel of the one at 48 (trilinear interpolation of a field with kinks near edges).
  ASSERT_EQ(rtsdfCmd("bake " + scene + " --res 40 -o " + q(dir / "coarse.vdb")).exitCode, 0);
  const Result resampled = rtsdfCmd("compare " + q(dir / "exact.vdb") + " " + q(dir / "coarse.vdb"));
  ASSERT_EQ(resampled.exitCode, 0) << resampled.output;
  EXPECT_NE(resampled.output.find("resampled at A's voxel centres"), std::string::npos) << resampled.output;
  const double mean = numberAfter(resampled.output, "|A - B|    mean ");
  EXPECT_GT(mean, 0.0) << resampled.output;
  EXPECT_LT(mean, 0.1) << resampled.output;

  // Against the exact anchor baked on its own voxels, the exact file itself differs by nothing.
  const Result anchored = rtsdfCmd("compare " + q(dir / "exact.vdb") + " --against exact");
  ASSERT_EQ(anchored.exitCode, 0) << anchored.output;
  EXPECT_EQ(numberAfter(anchored.output, "|A - B|    mean "), 0.0) << anchored.output;
  EXPECT_EQ(numberAfter(anchored.output, "compared   "), double(grid->activeVoxelCount())) << anchored.output;
  // The same anchor against a field whose difference the test knows independently: the exact file with a quarter
  // voxel added to every active value (written here, metadata kept) differs from the anchor by exactly that.
  {
    openvdb::FloatGrid::Ptr shifted = grid->deepCopy();
    const float quarter = 0.25f * float(grid->voxelSize()[0]);
    for (auto it = shifted->beginValueOn(); it; ++it) it.setValue(*it + quarter);
    writeVdb(dir / "shifted.vdb", {shifted});
  }
  const Result shiftedCmp = rtsdfCmd("compare " + q(dir / "shifted.vdb") + " --against exact");
  ASSERT_EQ(shiftedCmp.exitCode, 0) << shiftedCmp.output;
  EXPECT_EQ(numberAfter(shiftedCmp.output, "compared   "), double(grid->activeVoxelCount())) << shiftedCmp.output;
  EXPECT_NEAR(numberAfter(shiftedCmp.output, "|A - B|    mean "), 0.25, 1e-3) << shiftedCmp.output;
  EXPECT_NEAR(numberAfter(shiftedCmp.output, ", max "), 0.25, 1e-3) << shiftedCmp.output;
  const Result both = rtsdfCmd("compare " + q(dir / "exact.vdb") + " " + q(dir / "vdb.vdb") + " --against exact");
  EXPECT_NE(both.exitCode, 0);
  EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
}

// compare's numbers against a closed form: two exact sphere fields on the same voxels whose radii differ by one
// voxel differ by exactly one voxel wherever both are active, and disagree in sign between the two surfaces.
TEST(Cli, CompareOfTwoSpheresReportsTheirRadiusDifference) {
  TempDir dir;
  const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 40, 0.2); // voxels of 0.05
  const double r1 = 0.6, r2 = 0.65, band = 0.3;
  for (const auto& [name, r] : {std::pair{"a.vdb", r1}, std::pair{"b.vdb", r2}}) {
    auto grid = denseToLevelSet(test::sphereField(g, {0, 0, 0}, r), g, float(band));
    stampLevelSet(*grid, g, {{"method", "test"}});
    writeVdb(dir / name, {grid});
  }
  std::uint64_t both = 0, between = 0; // brute force over the voxel centres, in float as the grids hold them
  for (int z = 0; z < g.dims.z; ++z)
    for (int y = 0; y < g.dims.y; ++y)
      for (int x = 0; x < g.dims.x; ++x) {
        const double d = glm::length(g.indexToWorld(glm::dvec3(x, y, z)));
        const float da = float(d - r1), db = float(d - r2);
        if (std::fabs(da) > float(band) || std::fabs(db) > float(band)) continue;
        ++both;
        between += (da < 0) != (db < 0);
      }
  const Result r = rtsdfCmd("compare " + q(dir / "a.vdb") + " " + q(dir / "b.vdb"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(numberAfter(r.output, "compared   "), double(both)) << r.output;
  EXPECT_NEAR(numberAfter(r.output, "|A - B|    mean "), 1.0, 1e-4) << r.output;
  EXPECT_NEAR(numberAfter(r.output, ", RMS "), 1.0, 1e-4) << r.output;
  EXPECT_NEAR(numberAfter(r.output, ", max "), 1.0, 1e-4) << r.output;
  EXPECT_GT(between, 100u);
  EXPECT_EQ(numberAfter(r.output, "sign       "), double(between)) << r.output;
}

TEST(Cli, BakesAMeshFileDirectlyAndTheFullDomain) {
  TempDir dir;
  const Result r = rtsdfCmd("bake " + q(test::dataPath("meshes/bunny.obj")) + " --res 24 --full -o " + q(dir / "b.vdb"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto grid = readLevelSet(dir / "b.vdb");
  const GridSpec spec = gridSpecOf(*grid);
  EXPECT_EQ(grid->activeVoxelCount(), spec.voxelCount());
}

TEST(Cli, BakesTheGpuCoarseSdf) {
  TempDir dir;
  const Result r = rtsdfCmd("bake " + q(test::dataPath("scenes/default.json")) +
                            " --method jfa --coarse 40 --jfa jfa+2 --band 0.1 -o " + q(dir / "coarse.vdb"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("JumpFloodPass"), std::string::npos) << r.output;
  const auto grid = readLevelSet(dir / "coarse.vdb");
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:method"), "jfa");
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:coarse_method"), "jfa+2");
  EXPECT_EQ(gridSpecOf(*grid).dims.x, 44); // 40 across the scene plus the band's padding
  EXPECT_GT(grid->activeVoxelCount(), 1000u);
  // The coarse field is distance minus beta: its minimum is -beta (half a voxel by default) on the seeds.
  float lo = 0.0f;
  for (auto it = grid->cbeginValueOn(); it; ++it) lo = std::min(lo, *it);
  EXPECT_NEAR(lo, -0.5 * grid->voxelSize()[0], 1e-6);

  // The default coarse method is the exact transform: never farther than jump flooding's nearest seed.
  const Result exact = rtsdfCmd("bake " + q(test::dataPath("scenes/default.json")) +
                                " --method jfa --coarse 40 --band 0.1 -o " + q(dir / "exact.vdb"));
  ASSERT_EQ(exact.exitCode, 0) << exact.output;
  EXPECT_NE(exact.output.find("ExactEdtPass"), std::string::npos) << exact.output;
  const auto exactGrid = readLevelSet(dir / "exact.vdb");
  EXPECT_EQ(exactGrid->metaValue<std::string>("rtsdf:coarse_method"), "edt");
  std::size_t compared = 0;
  const auto jfaAccess = grid->getConstAccessor();
  for (auto it = exactGrid->cbeginValueOn(); it; ++it) {
    float j = 0.0f;
    if (!jfaAccess.probeValue(it.getCoord(), j)) continue;
    ++compared;
    ASSERT_LE(*it, j + 1e-6f) << it.getCoord();
  }
  EXPECT_GT(compared, 1000u);

  const Result bad = rtsdfCmd("bake " + q(test::dataPath("scenes/default.json")) +
                              " --method jfa --device no-such-gpu -o " + q(dir / "x.vdb"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.output.find("no-such-gpu"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.vdb"));
  const Result big = rtsdfCmd("bake " + q(test::dataPath("scenes/default.json")) + " --method jfa --coarse 2000 -o " +
                              q(dir / "y.vdb"));
  EXPECT_NE(big.exitCode, 0);
  EXPECT_NE(big.output.find("--coarse"), std::string::npos) << big.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "y.vdb"));
}

TEST(Cli, BakesTheRefinedSdfAndAnimates) {
  TempDir dir;
  const std::string scene = q(test::dataPath("scenes/default.json"));
  const Result r = rtsdfCmd("bake " + scene + " --method rtsdf --coarse 24 --fine 48 --rays 2 --frames 2 --refine rays --band 0.1 -o " +
                            q(dir / "fine.vdb"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("RayRefinePass"), std::string::npos) << r.output;
  const auto grid = readLevelSet(dir / "fine.vdb");
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:method"), "rtsdf");
  EXPECT_EQ(grid->metaValue<int>("rtsdf:rays"), 2);
  EXPECT_GT(grid->activeVoxelCount(), 1000u);

  std::filesystem::create_directories(dir / "frames");
  const Result a = rtsdfCmd("animate " + scene + " --frames 3 --coarse 16 --fine 32 --rays 2 --refine rays --band 0.1 --csv " +
                            q(dir / "stats.csv") + " --vdb-dir " + q(dir / "frames"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  std::ifstream csv(dir / "stats.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("mean_abs_error_voxels"), std::string::npos);
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    // frame, time, mask_coarse, mask_fine, 6 pass times, band_voxels, mean, max, wrong_sign_rate, refined_fine
    std::vector<double> v;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) v.push_back(std::strtod(cell.c_str(), nullptr));
    ASSERT_EQ(v.size(), 15u) << line;
    EXPECT_EQ(v[3], 8 * v[2]) << "fine 32 over coarse 16: 8 fine voxels per masked coarse voxel: " << line;
    // Rays mode settles after 32 refinements: every masked voxel is refined in these three frames.
    EXPECT_EQ(v[14], v[3]) << line;
    EXPECT_GT(v[10], 1000) << line;
    // Measured on lavapipe: mean 0.19-0.26 voxels, max 1.39-1.45, wrong signs 4e-4 at most.
    EXPECT_TRUE(v[11] > 0.0 && v[11] < 0.4) << line;
    EXPECT_TRUE(v[12] >= v[11] && v[12] < 2.2) << line;
    EXPECT_TRUE(v[13] >= 0.0 && v[13] < 2e-3) << line;
  }
  EXPECT_EQ(rows, 3);
  EXPECT_TRUE(std::filesystem::exists(dir / "frames" / "frame0002.vdb"));

  for (const std::string& bad : {std::string("--alpha 2"), std::string("--rays -1"), std::string("--fine 8 --coarse 16")}) {
    const Result b = rtsdfCmd("bake " + scene + " --method rtsdf " + bad + " -o " + q(dir / "bad.vdb"));
    EXPECT_NE(b.exitCode, 0) << bad;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.vdb")) << bad;
  }
}

TEST(Cli, BenchFrameSuiteWritesOneCsvRowPerFrame) {
  TempDir dir;
  const std::string scene = q(test::dataPath("scenes/default.json"));
  // Incremental runs with x = 0 settle after one refinement; the full recompute refines the whole mask. The first
  // case warms up (default): its times come from a timed run and its errors from a second run of the same frames.
  struct Case { const char* flags; bool still, full; };
  for (const Case& c : {Case{" --rays 0", false, false}, Case{" --rays 0 --still --warm-up 0", true, false},
                        Case{" --full-recompute --warm-up 0", false, true},
                        Case{" --rays 0 --fine-storage sparse --warm-up 0", false, false}}) {
    SCOPED_TRACE(c.flags);
    const bool still = c.still;
    const Result r = rtsdfCmd("bench " + scene + " --suite frame --size S --frames 3 --csv " + q(dir / "frames.csv") +
                              " -o " + q(dir / "frames.md") + c.flags);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("Medians of frames 2..N"), std::string::npos) << r.output;
    const bool warmed = std::string(c.flags).find("--warm-up 0") == std::string::npos;
    EXPECT_EQ(r.output.find("run back to back after 1 s of warm-up frames") != std::string::npos, warmed) << r.output;
    std::ifstream csv(dir / "frames.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header, "frame,host_ms,gpu_ms,wall_ms,mask_voxels,refined_voxels,mean_abs_error_voxels,wrong_sign_pct,"
                      "peak_mib,time,active_bricks,pool_bricks,overflow_bricks,device_mib,coarse_voxelized,"
                      "coarse_rebuilt,mask_visited,upsampled");
    std::vector<std::vector<double>> rows;
    while (std::getline(csv, line)) {
      std::vector<double> v;
      std::stringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) v.push_back(std::strtod(cell.c_str(), nullptr));
      ASSERT_EQ(v.size(), 18u) << line;
      rows.push_back(v);
    }
    ASSERT_EQ(rows.size(), 3u);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::vector<double>& v = rows[i];
      EXPECT_EQ(v[0], double(i + 1));
      EXPECT_GT(v[1], 0.0);                       // host
      if (still && i == 2) EXPECT_EQ(v[2], 0.0);  // nothing moved or settles: every pass skipped
      else EXPECT_GT(v[2], 0.0);                  // GPU passes
      EXPECT_GE(v[3], v[1]);                      // wall includes the host's part
      EXPECT_GT(v[4], 10000.0);                   // mask
      if (c.full || i == 0) EXPECT_EQ(v[5], v[4]); // every masked voxel refined
      else if (still) EXPECT_EQ(v[5], 0.0);       // nothing moved, every voxel settled
      else EXPECT_TRUE(v[5] > 0.0 && v[5] < 0.5 * v[4]) << line; // near the orbiting teapot only
      EXPECT_TRUE(v[6] > 0.0 && v[6] < 0.5) << line; // closest mode at S: a fraction of a voxel
      EXPECT_TRUE(v[7] >= 0.0 && v[7] < 1.0) << line;
      EXPECT_GT(v[8], 1.0);                       // peak MiB
      if (still) {
        EXPECT_EQ(v[9], 0.0);
        EXPECT_EQ(v[4], rows[0][4]); // the same scene, the same mask
      } else {
        EXPECT_NEAR(v[9], i / 30.0, 1e-6);
      }
      // Bricks of 512 voxels hold the mask, every one with a slot in the pool the first frame's band sized.
      EXPECT_GE(v[10] * 512.0, v[4]) << line;
      EXPECT_TRUE(v[11] >= v[10] && v[11] == std::floor(1.5 * rows[0][10]) + 64.0) << line;
      EXPECT_EQ(v[12], 0.0) << line;
      EXPECT_GT(v[13], 1.0) << line; // device MiB
      // Voxels touched: the first frame (and every frame of a full recompute) builds the whole coarse grid; a frame
      // where the teapot moved voxelizes its seed box alone; a still frame builds nothing.
      if (c.full || i == 0) EXPECT_TRUE(v[14] > 0.0 && v[15] == v[14] && v[16] == v[14]) << line;
      else if (still) EXPECT_TRUE(v[14] == 0.0 && v[15] == 0.0) << line;
      else EXPECT_TRUE(v[14] > 0.0 && v[14] < 0.1 * rows[0][14] && v[15] >= v[14]) << line;
    }
  }
}

// The cascade suite on a generated 50 m town (2 levels of coarse 64 / fine 128, 3 frames per run, shaded at 32x18):
// each camera speed runs incrementally, with every pass of every level rebuilt, and through the renderer, on the same
// camera path, so every build moves the same levels each frame, the full rebuild refines at least as many voxels and
// the renderer's levels refine the same voxels as the incremental run's; every level's error at the last frame is
// reported.
TEST(Cli, BenchCascadeSuiteFollowsTheCameraPathAgainstAFullRebuild) {
  TempDir dir;
  int status = 0;
  const std::string log = test::runCommand("/usr/bin/python3 " + q(test::dataPath("../scripts/make_level.py")) +
                                               " --out " + q(dir / "town") + " --size 50 2>&1",
                                           status);
  ASSERT_EQ(status, 0) << log;
  const Result r = rtsdfCmd("bench " + q(dir / "town" / "level.json") + " --suite cascade --cascades 2 " +
                            "--cascade-extent 12.5 --size S --frames 3 --rays 0 --shade 32 18 --warm-up 0 --csv " +
                            q(dir / "c.csv") + " -o " + q(dir / "c.md"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("cascade suite 18/18 done in"), std::string::npos) << r.output;
  std::ifstream md(dir / "c.md");
  const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  for (const char* part : {"| walking | incremental / full rebuild |", "| driving | incremental / full rebuild |",
                           "| walking | shaded 32x18 |", "| driving | shaded 32x18 |", "| ClosestRefinePass |",
                           "| SdfShadowPass |", "| walking | 1 |", "| driving | 1 |",
                           "| coarse voxels voxelized (VoxelizePass) |"})
    EXPECT_NE(report.find(part), std::string::npos) << part << "\n" << report;
  std::ifstream csv(dir / "c.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "scene,camera,build,frame,time,speed,levels_moved,levels_recut,levels_rebuilt,move_ms,gpu_ms,"
                    "wall_ms,refined_voxels,device_mib,kept_voxels,coarse_voxelized,coarse_rebuilt,mask_visited,"
                    "upsampled");
  struct Row {
    std::string camera, build;
    int frame = 0, moved = 0;
    double time = 0, speed = 0, gpu = 0;
    long refined = 0, kept = 0, voxelized = 0, rebuilt = 0;
  };
  std::vector<Row> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 19u) << line;
    rows.push_back({c[1], c[2], std::stoi(c[3]), std::stoi(c[6]), std::stod(c[4]), std::stod(c[5]), std::stod(c[10]),
                    std::stol(c[12]), std::stol(c[14]), std::stol(c[15]), std::stol(c[16])});
  }
  ASSERT_EQ(rows.size(), 18u); // walking and driving; incremental, full rebuild and shaded; 3 frames each
  const char* builds[] = {"incremental", "full rebuild", "shaded 32x18"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    SCOPED_TRACE(row.camera + " " + row.build + " frame " + std::to_string(row.frame));
    EXPECT_EQ(row.frame, int(i % 3) + 1);
    EXPECT_EQ(row.camera, i < 9 ? "walking" : "driving");
    EXPECT_EQ(row.build, builds[i % 9 / 3]);
    EXPECT_LT(row.speed, 100.0);
    if (row.camera == "walking") EXPECT_LT(row.speed, 4.0);
    else EXPECT_GT(row.speed, 4.0);
    // An incremental frame where no level moved and nothing moved near one runs no pass at all; a full rebuild runs
    // every pass, and a shaded frame at least the shading.
    if (row.build == "incremental") EXPECT_GE(row.gpu, 0.0);
    else EXPECT_GT(row.gpu, 0.0);
    EXPECT_LE(row.kept, row.refined); // the voxels listed for a moving car alone and kept unwalked
    // A full rebuild voxelizes and rebuilds every level's whole coarse grid; what changed is a part of that.
    if (row.build == "full rebuild") EXPECT_TRUE(row.voxelized > 0 && row.rebuilt == row.voxelized) << row.voxelized;
    if (i % 9 < 3) continue;
    const Row& incremental = rows[i - i % 9 + i % 3]; // the incremental run's frame of the same moment
    EXPECT_EQ(row.time, incremental.time);
    EXPECT_EQ(row.moved, incremental.moved);
    if (i % 9 < 6) { // the full rebuild: every masked voxel walked
      EXPECT_GE(row.refined, incremental.refined);
      EXPECT_GT(row.refined, 0);
      EXPECT_EQ(row.kept, 0);
      EXPECT_GE(row.voxelized, incremental.voxelized);
    } else { // the renderer's levels: the same frames of the same levels
      EXPECT_EQ(row.refined, incremental.refined);
      EXPECT_EQ(row.voxelized, incremental.voxelized);
      EXPECT_EQ(row.kept, incremental.kept);
    }
  }
}

TEST(Cli, InfoListsAVulkanDevice) {
  const Result r = rtsdfCmd("info");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("OpenVDB"), std::string::npos);
  EXPECT_NE(r.output.find("Vulkan devices"), std::string::npos);
  EXPECT_NE(r.output.find("fill.comp"), std::string::npos);
}

TEST(Cli, BadInputIsRefusedClearlyWithNoOutputFile) {
  TempDir dir;
  writeText(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  writeText(dir / "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n");
  writeText(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  writeText(dir / "empty.obj", "# nothing here\n");
  writeText(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  writeText(dir / "broken.json", "{\"meshes\": {");
  writeText(dir / "typo.json", R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", "scael": 2}]})");
  writeText(dir / "missing-mesh.json", R"({"meshes": {"m": {"path": "gone.obj"}}, "instances": [{"mesh": "m"}]})");
  const std::string ok = q(test::dataPath("scenes/bunny.json"));
  struct Case { std::string args; std::string expect; };
  const std::vector<Case> cases = {
      {q(dir / "absent.json"), "absent.json: scene file not found"},
      {q(dir / "nan.obj"), "nan.obj"},
      {q(dir / "inf.obj"), "inf.obj"},
      {q(dir / "range.obj"), "range.obj"},
      {q(dir / "empty.obj"), "empty.obj"},
      {q(dir / "flat.obj"), "flat.obj"},
      {q(dir / "broken.json"), "broken.json: malformed JSON"},
      {q(dir / "typo.json"), "unknown key 'scael'"},
      {q(dir / "missing-mesh.json"), "gone.obj: mesh file not found"},
      {ok + " --res 0", "--res"},
      {ok + " --res 100000", "--res"},
      {ok + " --band -1", "--band"},
      {ok + " --band nan", "--band"},
      {ok + " --band 0", "--band"},
      {ok + " --method magic", "--method"},
      {ok + " --method openvdb --full", "--full: a full-domain field needs the exact method"},
      {ok + " --res 8192", "GiB"}, // too large for memory: refused before allocating
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const auto out = dir / "out.vdb";
    const Result r = rtsdfCmd("bake " + c.args + " -o " + q(out));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  // Output that cannot be written is refused before any work.
  const Result noDir = rtsdfCmd("bake " + ok + " -o " + q(dir / "nowhere" / "x.vdb"));
  EXPECT_NE(noDir.exitCode, 0);
  EXPECT_NE(noDir.output.find("does not exist"), std::string::npos) << noDir.output;
  const Result isDir = rtsdfCmd("bake " + ok + " -o " + q(dir.path()));
  EXPECT_NE(isDir.exitCode, 0);
  // Nothing but the inputs is left in the folder (no temporaries).
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 8u);
  // compare names the file it cannot read.
  writeText(dir / "junk.vdb", "junk");
  const Result junk = rtsdfCmd("compare " + q(dir / "junk.vdb") + " " + q(dir / "junk.vdb"));
  EXPECT_NE(junk.exitCode, 0);
  EXPECT_NE(junk.output.find("junk.vdb"), std::string::npos) << junk.output;
}

namespace {
std::string fileBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
} // namespace

// An output never replaces an input and always carries its format's extension; a render that fails on its last
// file leaves none of the others. Each is refused with a message naming the path and a non-zero exit.
TEST(Cli, OutputsNeverReplaceInputsAndMatchTheirFormat) {
  const TempDir dir;
  const auto mesh = dir / "in.obj";
  std::filesystem::copy_file(test::dataPath("meshes/teapot.obj"), mesh);
  const std::string before = fileBytes(mesh);
  struct Case { std::string args; std::string expect; std::filesystem::path absent; };
  const std::vector<Case> bakes = {
      {"-o " + q(mesh), "would replace an input", {}},
      {"-o " + q(dir / "x.txt"), "give it the extension .vdb", dir / "x.txt"},
      {"-o ''", "the output path is empty", {}},
  };
  for (const Case& c : bakes) {
    SCOPED_TRACE(c.args);
    const Result r = rtsdfCmd("bake " + q(mesh) + " --res 16 " + c.args);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    if (!c.absent.empty()) EXPECT_FALSE(std::filesystem::exists(c.absent));
  }
  EXPECT_EQ(fileBytes(mesh), before) << "the input mesh changed";

  const std::string scene = q(test::dataPath("scenes/analytic.json"));
  const std::string small = "-q render " + scene + " --shadows shadowmap --width 16 --height 9 ";
  const std::vector<Case> renders = {
      {"-o " + q(dir / "y.png"), "give it the extension .exr", dir / "y.png"},
      {"-o " + q(dir / "y.exr") + " --png " + q(dir / "y.exr"), "give it the extension .png", dir / "y.exr"},
      // The PNG cannot be written: the EXR written before it is removed again.
      {"-o " + q(dir / "z.exr") + " --png /proc/z.png", "z.png", dir / "z.exr"},
  };
  for (const Case& c : renders) {
    SCOPED_TRACE(c.args);
    const Result r = rtsdfCmd(small + c.args);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(c.absent));
  }
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1u) << "only the input mesh is left";
}

// render end to end: every technique writes an EXR (R, G, B and the light's visibility) and a PNG that read
// back; --compare prints the error against the truth and writes the error picture.
TEST(Cli, RendersTheAnalyticSceneWithEveryTechnique) {
  const TempDir dir;
  const std::string scene = q(test::dataPath("scenes/analytic.json"));
  // Each technique with its own flags: a flag of another technique is refused (jobs/SettingUse.h).
  const std::map<std::string, std::string> flagsOf = {{"sdf", "--frames 2 --coarse 32 --fine 64"},
                                                      {"shadowmap", "--frames 2 --shadow-map-res 256"},
                                                      {"raytraced", ""}};
  for (const char* t : {"sdf", "shadowmap", "raytraced"}) {
    SCOPED_TRACE(t);
    const auto exr = dir / (std::string(t) + ".exr");
    const Result r = rtsdfCmd("-q render " + scene + " --shadows " + t + " --width 64 --height 36 " +
                              flagsOf.at(t) + " --samples 16 --compare -o " + q(exr));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // The printed error against the truth (measured on lavapipe: sdf 0.0523, shadowmap 0.0644; the ray tracer's
    // 16 samples against a truth of 64 with another seed, 0.0243: its noise).
    const double rmse = numberAfter(r.output, "visibility RMSE "), flip = numberAfter(r.output, "FLIP ");
    const double limit = std::string(t) == "sdf" ? 0.08 : std::string(t) == "shadowmap" ? 0.1 : 0.04;
    EXPECT_LE(rmse, limit) << r.output;
    EXPECT_GT(rmse, 0.01) << r.output; // no picture, the ray tracer's included, matches an independent truth
    EXPECT_TRUE(flip >= 0.0 && flip <= 2.0 * limit) << r.output;
    // The error concentrates in the penumbrae: their RMSE is at least the whole picture's.
    EXPECT_GE(numberAfter(r.output, "penumbra RMSE "), rmse) << r.output;
    // Light in the truth's umbra: a visibility error of every technique.
    const double umbra = numberAfter(r.output, "umbra mean |diff| ");
    EXPECT_TRUE(umbra >= 0.0 && umbra <= 1.0) << r.output;
    const Image img = readExr(exr);
    EXPECT_EQ(img.width(), 64);
    EXPECT_EQ(img.height(), 36);
    for (const char* c : {"R", "G", "B", "sun.V"}) {
      ASSERT_TRUE(img.hasChannel(c)) << c;
      for (float v : img.channel(c)) ASSERT_TRUE(std::isfinite(v));
    }
    const PngPixels png = readPng(dir / (std::string(t) + ".png"));
    EXPECT_EQ(png.width, 64);
    EXPECT_TRUE(std::filesystem::exists(dir / (std::string(t) + "_error.png")));
  }
}

TEST(Cli, RenderRefusesBadInputWithoutWritingAnything) {
  const TempDir dir;
  writeText(dir / "nocamera.json", R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b"}],
    "lights": [{"type": "directional", "direction": [0, -1, 0]}]})");
  writeText(dir / "nolight.json", R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b"}],
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}})");
  const std::string ok = q(test::dataPath("scenes/analytic.json"));
  struct Case { std::string args; std::string expect; };
  const std::vector<Case> cases = {
      {q(dir / "nocamera.json"), "no camera"},
      {q(dir / "nolight.json"), "no light"},
      {q(dir / "absent.json"), "absent.json"},
      {ok + " --shadows magic", "--shadows"},
      {ok + " --epsilon 0.5", "--epsilon"},
      {ok + " --bias -0.1", "--bias"},
      {ok + " --min-step 0.01", "--min-step"},
      {ok + " --width 0", "--width"},
      {ok + " --max-step 0", "--max-step"},
      {ok + " --taa-blend 0", "--taa-blend"},
      // Three lights' depth maps at 8192 need 4.5 GiB: beyond every device's limit (a 32-bit byte count).
      {q(dir / "three_suns.json") + " --shadows shadowmap --shadow-map-res 8192", "storage buffer limit"},
  };
  writeText(dir / "three_suns.json", R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b"}],
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
    "lights": [{"name": "a", "type": "directional", "direction": [0, -1, 0]},
               {"name": "b", "type": "directional", "direction": [1, -1, 0]},
               {"name": "c", "type": "directional", "direction": [0, -1, 1]}]})");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const Result r = rtsdfCmd("-q render " + c.args + " --width 16 --height 9 -o " + q(dir / "out.exr"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.exr"));
    EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
  }
  const Result noDir = rtsdfCmd("-q render " + ok + " -o " + q(dir / "nowhere" / "x.exr"));
  EXPECT_NE(noDir.exitCode, 0);
  EXPECT_NE(noDir.output.find("does not exist"), std::string::npos) << noDir.output;
}

namespace {
std::size_t lineCount(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}
} // namespace

TEST(Cli, SweepWritesCsvReportAndPlots) {
  TempDir dir;
  const auto out = dir / "sweep";
  const Result r = rtsdfCmd("bench " + q(test::dataPath("scenes/teapot.json")) + " --sweep quick --truth-samples 16 --out " +
                            q(out));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("ETA"), std::string::npos) << "progress with an ETA";
  // Header plus one row per point (a Dynamic point adds one row per frame).
  EXPECT_GE(lineCount(out / "sweep.csv"), 20u);
  std::ifstream md(out / "report.md");
  const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  for (const char* section : {"Pass durations and sizes x rays", "Anchors", "Band d x rays", "History decay",
                              "Frames accumulated", "Coarse method (exact transform or jump-flooding variant)", "Storage", "Pareto front", "pareto.png"})
    EXPECT_NE(report.find(section), std::string::npos) << section;
  EXPECT_EQ(report.find("failed:"), std::string::npos) << report;
  for (const char* png : {"pareto.png", "time_vs_work.png", "error_vs_frames.png"})
    EXPECT_GT(readPng(out / png).width, 500) << png;
}

TEST(Cli, SweepInterruptedByCtrlCKeepsTheFinishedPoints) {
  TempDir dir;
  const auto out = dir / "sweep";
  const std::string bin = RTSDF_BINARY, scene = test::dataPath("scenes/bunny.json"), outDir = out.string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stderr);
    std::freopen("/dev/null", "w", stdout);
    execl(bin.c_str(), bin.c_str(), "bench", scene.c_str(), "--sweep", "default", "--no-shadows", "--out",
          outDir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait for the first finished points (a header and two rows), then press Ctrl-C. No wall-clock limit: the
  // wait ends when the rows are there or the sweep has ended without them (ctest's timeout stops a hang).
  int status = 0;
  bool ended = false;
  while (lineCount(out / "sweep.csv") < 3 && !(ended = waitpid(pid, &status, WNOHANG) == pid))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::size_t before = lineCount(out / "sweep.csv");
  ASSERT_FALSE(ended) << "the sweep ended before two points finished";
  kill(pid, SIGINT);
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_GE(lineCount(out / "sweep.csv"), before) << "finished rows are kept";
  std::ifstream md(out / "report.md");
  const std::string report((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("INTERRUPTED"), std::string::npos);
  EXPECT_NE(report.find("Pass durations"), std::string::npos);
}

TEST(Cli, SweepRefusesBadInputWithoutCreatingItsFolder) {
  TempDir dir;
  const auto out = dir / "sweep";
  const std::string scene = q(test::dataPath("scenes/bunny.json"));
  Result r = rtsdfCmd("bench " + q(dir / "missing.json") + " --sweep quick --out " + q(out));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  r = rtsdfCmd("bench " + scene + " " + scene + " --sweep quick --out " + q(out));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("one scene"), std::string::npos) << r.output;
  r = rtsdfCmd("bench " + scene + " --sweep fast --out " + q(out));
  EXPECT_NE(r.exitCode, 0);
  r = rtsdfCmd("bench " + scene + " --sweep quick --out " + q(dir / "no" / "such" / "folder"));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  writeText(dir / "file", "x");
  r = rtsdfCmd("bench " + scene + " --sweep quick --out " + q(dir / "file"));
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.output.find("not a folder"), std::string::npos) << r.output;
}

// A bake records its scene by absolute path and by the path from the .vdb's folder: compare --against finds it from
// any folder, and after the scene and the bake move together.
TEST(Cli, CompareAgainstExactFindsTheSceneFromAnotherFolderAndAfterAMove) {
  TempDir dir;
  std::filesystem::create_directories(dir / "project" / "scenes");
  std::filesystem::create_directories(dir / "project" / "out");
  std::filesystem::copy_file(test::dataPath("meshes/bunny.obj"), dir / "project" / "scenes" / "bunny.obj");
  // Baked from the scene's folder with a relative path, as a user types it.
  const std::string inScenes = "cd " + q(dir / "project" / "scenes") + " && " + std::string(RTSDF_BINARY);
  int status = 0;
  const std::string baked = test::runCommand(inScenes + " bake bunny.obj --res 24 --band 0.9 -o ../out/b.vdb 2>&1",
                                             status);
  ASSERT_EQ(status, 0) << baked;
  const auto grid = readLevelSet(dir / "project" / "out" / "b.vdb");
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:scene"), (dir / "project" / "scenes" / "bunny.obj").string());
  EXPECT_EQ(grid->metaValue<std::string>("rtsdf:scene_relative"), "../scenes/bunny.obj");
  EXPECT_EQ(grid->metaValue<double>("rtsdf:band"), 0.9);
  EXPECT_EQ(grid->metaValue<int>("rtsdf:resolution"), 24);
  // From another folder: the absolute path.
  const std::string elsewhere = "cd / && " + std::string(RTSDF_BINARY);
  std::string out = test::runCommand(elsewhere + " compare " + q(dir / "project" / "out" / "b.vdb") +
                                     " --against exact 2>&1", status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("max 0.0000 voxels"), std::string::npos) << out;
  EXPECT_NE(out.find("0 voxels disagree"), std::string::npos) << out;
  // Moved with its scene: the path relative to the .vdb.
  std::filesystem::rename(dir / "project", dir / "moved");
  out = test::runCommand(elsewhere + " compare " + q(dir / "moved" / "out" / "b.vdb") + " --against exact 2>&1",
                         status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find((dir / "moved" / "scenes" / "bunny.obj").string()), std::string::npos) << out;
  EXPECT_NE(out.find("max 0.0000 voxels"), std::string::npos) << out;
}

// --up z turns every .vdb a command writes: a bake and animate's frames.
TEST(Cli, UpZTurnsTheBakeAndTheAnimatedFrames) {
  TempDir dir;
  const std::string scene = q(test::dataPath("scenes/default.json"));
  const Result b = rtsdfCmd("bake " + scene + " --res 24 --up z -o " + q(dir / "z.vdb"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  const auto baked = readLevelSet(dir / "z.vdb");
  EXPECT_EQ(upAxisOf(*baked), UpAxis::Z);
  EXPECT_EQ(gridSpecOf(*baked).dims, gridSpecOf(*inSceneFrame(baked)).dims);
  std::filesystem::create_directories(dir / "frames");
  const Result a = rtsdfCmd("animate " + scene + " --frames 1 --coarse 8 --fine 16 --up z --vdb-dir " +
                            q(dir / "frames"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  const auto frame = readLevelSet(dir / "frames" / "frame0000.vdb");
  EXPECT_EQ(upAxisOf(*frame), UpAxis::Z);
  EXPECT_EQ(frame->metaValue<int>("rtsdf:resolution"), 16);
}

// Every GPU job refuses its results after a Vulkan validation error, one reported at the device's destruction (an
// object left alive) included. The build's test hook (RTSDF_TEST_VALIDATION_ERROR) commits a deliberate one; the
// same commands pass without it. (The sweep's check: SweepRunner.FinishRefusesASweepWithAValidationError.)
TEST(Cli, AValidationErrorFailsRenderAndTheBenchSuites) {
  const TempDir dir;
  const std::string scene = q(test::dataPath("scenes/analytic.json"));
  const std::string mesh = q(test::dataPath("meshes/bunny.obj"));
  const std::vector<std::string> commands = {
      "-q render " + scene + " --shadows sdf --width 32 --height 18 --coarse 32 --fine 64 -o " + q(dir / "r.exr"),
      "-q bench " + mesh + " --suite coarse --res 32 --repeats 1 --warm-up 0 -o " + q(dir / "coarse.md"),
  };
  for (const std::string& cmd : commands) {
    SCOPED_TRACE(cmd);
    ASSERT_EQ(::unsetenv("RTSDF_TEST_VALIDATION_ERROR"), 0);
    const Result clean = rtsdfCmd(cmd);
    ASSERT_EQ(clean.exitCode, 0) << clean.output;
    for (const char* kind : {"now", "leak"}) {
      SCOPED_TRACE(kind);
      ASSERT_EQ(::setenv("RTSDF_TEST_VALIDATION_ERROR", kind, 1), 0);
      const Result r = rtsdfCmd(cmd);
      ::unsetenv("RTSDF_TEST_VALIDATION_ERROR");
      EXPECT_NE(r.exitCode, 0) << r.output;
      EXPECT_NE(r.output.find("Vulkan validation reported"), std::string::npos) << r.output;
    }
  }
}

// A scene's mesh path that leaves the folder holding the scene's folder is refused by default (a row of the
// bad-input table); --allow-outside-references lets bake read it, and the field is the one of the mesh itself.
TEST(Cli, AllowOutsideReferencesLetsASceneReachItsMesh) {
  const TempDir dir;
  std::filesystem::create_directories(dir / "sub" / "scenes");
  std::filesystem::copy_file(test::dataPath("meshes/bunny.obj"), dir / "m.obj");
  writeText(dir / "sub" / "scenes" / "s.json",
            R"({"meshes": {"m": {"path": "../../m.obj"}}, "instances": [{"mesh": "m"}]})");
  const std::string scene = q(dir / "sub" / "scenes" / "s.json");
  const Result refused = rtsdfCmd("bake " + scene + " --res 16 -o " + q(dir / "refused.vdb"));
  EXPECT_NE(refused.exitCode, 0);
  EXPECT_NE(refused.output.find("'../../m.obj' is refused"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused.vdb"));

  const Result allowed = rtsdfCmd("bake " + scene + " --res 16 --allow-outside-references -o " + q(dir / "a.vdb"));
  ASSERT_EQ(allowed.exitCode, 0) << allowed.output;
  ASSERT_EQ(rtsdfCmd("bake " + q(dir / "m.obj") + " --res 16 -o " + q(dir / "direct.vdb")).exitCode, 0);
  const auto viaScene = readLevelSet(dir / "a.vdb"), direct = readLevelSet(dir / "direct.vdb");
  EXPECT_EQ(viaScene->activeVoxelCount(), direct->activeVoxelCount());
  EXPECT_GT(viaScene->activeVoxelCount(), 100u);
}

// --res is the output grid of every method (rtsdf: the fine grid; jfa: the coarse grid): a sphere of radius 1
// baked with only --res N has voxels 2 / N long, N across the sphere, whatever the method.
TEST(Cli, ResIsTheOutputGridOfEveryMethod) {
  TempDir dir;
  writeText(dir / "s.json", R"({"meshes": {"s": {"sphere": {"radius": 1}}}, "instances": [{"mesh": "s"}]})");
  const int n = 24;
  for (const char* method : {"exact", "openvdb", "jfa", "rtsdf"}) {
    const auto out = dir / (std::string(method) + ".vdb");
    const Result r = rtsdfCmd(fmt::format("bake {} -m {} --res {} -o {}", q(dir / "s.json"), method, n, q(out)));
    ASSERT_EQ(r.exitCode, 0) << method << ": " << r.output;
    const auto grid = readLevelSet(out);
    const double h = grid->voxelSize()[0];
    EXPECT_NEAR(2.0 / h, double(n), 1e-6) << method << ": the sphere is " << 2.0 / h << " voxels across";
    EXPECT_EQ(grid->metaValue<int>("rtsdf:resolution"), n) << method;
  }
  // --fine and --coarse override it.
  const Result r = rtsdfCmd(fmt::format("bake {} -m rtsdf --res {} --fine 32 --coarse 8 -o {}", q(dir / "s.json"),
                                        n, q(dir / "o.vdb")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NEAR(2.0 / readLevelSet(dir / "o.vdb")->voxelSize()[0], 32.0, 1e-6);
  EXPECT_EQ(readLevelSet(dir / "o.vdb")->metaValue<int>("rtsdf:coarse"), 8);
}

// The global flags are taken anywhere on the line, before or after the subcommand and its arguments.
TEST(Cli, GlobalFlagsWorkAnywhereOnTheLine) {
  TempDir dir;
  writeText(dir / "s.json", R"({"meshes": {"s": {"sphere": {"radius": 1}}}, "instances": [{"mesh": "s"}]})");
  for (const std::string& line : {"-q bake " + q(dir / "s.json") + " --res 16 -o " + q(dir / "a.vdb"),
                                  "bake " + q(dir / "s.json") + " -q --res 16 -o " + q(dir / "b.vdb"),
                                  "bake " + q(dir / "s.json") + " --res 16 -o " + q(dir / "c.vdb") + " -v"}) {
    const Result r = rtsdfCmd(line);
    EXPECT_EQ(r.exitCode, 0) << line << ": " << r.output;
  }
  // -q after the subcommand and its arguments silences the log's info lines as it does before them.
  const Result loud = rtsdfCmd("bake " + q(dir / "s.json") + " --res 16 -o " + q(dir / "d.vdb"));
  EXPECT_NE(loud.output.find("[info]"), std::string::npos) << loud.output;
  const Result quiet = rtsdfCmd("bake " + q(dir / "s.json") + " --res 16 -o " + q(dir / "e.vdb") + " -q");
  EXPECT_EQ(quiet.exitCode, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("[info]"), std::string::npos) << quiet.output;
}

// A bake whose stderr is a pipe still says what it is doing: one line per stage or every few seconds.
TEST(Cli, BakeOnAPipePrintsProgressLines) {
  TempDir dir;
  writeText(dir / "s.json", R"({"meshes": {"s": {"sphere": {"radius": 1}}}, "instances": [{"mesh": "s"}]})");
  const Result r = rtsdfCmd("bake " + q(dir / "s.json") + " -m rtsdf --res 32 --preset paper --frames 3 -o " +
                            q(dir / "a.vdb") + " 2>&1 | cat");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("refining 3/3"), std::string::npos) << r.output;
  const Result quiet = rtsdfCmd("bake " + q(dir / "s.json") + " -m rtsdf --res 32 --frames 3 -q -o " +
                                q(dir / "b.vdb") + " 2>&1 | cat");
  EXPECT_EQ(quiet.output.find("refining"), std::string::npos) << quiet.output;
}

// Render, animate, compare --against and the bench suites on a pipe say what they do too: a line when each stage
// ends (and every few seconds within it, with the time left); -q prints none.
TEST(Cli, RenderAnimateCompareAndBenchOnAPipePrintProgressLines) {
  TempDir dir;
  writeText(dir / "s.json", R"({"meshes": {"s": {"sphere": {"radius": 1}}}, "instances": [{"mesh": "s"}]})");
  ASSERT_EQ(rtsdfCmd("-q bake " + q(dir / "s.json") + " --res 16 -o " + q(dir / "a.vdb")).exitCode, 0);
  const std::string analytic = q(test::dataPath("scenes/analytic.json"));
  struct Case {
    std::string args;
    std::vector<std::string> lines;
  };
  const std::vector<Case> cases = {
      {"render " + analytic + " --frames 2 --width 32 --height 18 --coarse 16 --fine 32 -o " + q(dir / "r.exr"),
       {"render 2/2 done in"}},
      {"render " + analytic + " --width 32 --height 18 --coarse 16 --fine 32 --frames 2 --compare --samples 4 -o " +
           q(dir / "c.exr"),
       {"render 2/2 done in", "ray tracing 18/18 done in"}},
      {"animate " + q(dir / "s.json") + " --frames 2 --coarse 8 --fine 16", {"animate 2/2 done in"}},
      {"compare " + q(dir / "a.vdb") + " --against exact", {"exact SDF ", "baking the anchor 1/1 done in"}},
      {"bench " + q(dir / "s.json") + " --suite reference --res 8 --repeats 1", {"reference suite 1/1 done in"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const Result r = rtsdfCmd(c.args + " 2>&1 | cat");
    for (const std::string& line : c.lines) EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
    // A stage inside another (the anchor's exact bake) does not end the outer one early.
    EXPECT_EQ(r.output.find("baking the anchor 0/1"), std::string::npos) << r.output;
    const Result quiet = rtsdfCmd("-q " + c.args + " 2>&1 | cat");
    EXPECT_EQ(quiet.output.find(" done in "), std::string::npos) << quiet.output;
    EXPECT_EQ(quiet.output.find("s left"), std::string::npos) << quiet.output;
  }
}
