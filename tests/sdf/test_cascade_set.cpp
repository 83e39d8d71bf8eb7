// Cascade levels on lavapipe: each level's part of the scene gives the field the whole scene gives on the level's
// voxels, the refined voxels are the exact distance, a camera move rebuilds only the levels whose box moved, and a
// bake writes one level set per level that compare checks on each level's own voxels.
#include "CascadeTestLevels.h"
#include "GpuFixture.h"
#include "TestUtil.h"
#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/CascadeBake.h"
#include "jobs/Compare.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/cascade/CascadeFaults.h"
#include "sdf/cascade/CascadeSet.h"
#include "sdf/pipeline/GpuRayMask.h"
#include "sdf/pipeline/GridShift.h"
#include "sdf/pipeline/PipelineProbe.h"
#include "util/Error.h"

#include <gtest/gtest.h>

using namespace rtsdf;

namespace {

struct CascadeTag : test::NoSuiteObjects {};
using CascadeSetGpu = test::VulkanSuite<CascadeTag>;

using test::largestDifference;
using test::threeLevels;

Scene room() { return loadScene(test::dataPath("scenes/default.json")); }

std::uint64_t differing(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}


} // namespace

TEST_F(CascadeSetGpu, EachLevelEqualsTheWholeSceneOnItsVoxelsAndIsExactUnderItsBand) {
  const Scene scene = room();
  const PipelineSettings s = threeLevels();
  const glm::dvec3 camera(-0.3, 0.45, 0.1);
  const CascadeLayout layout = CascadeLayout::around(camera, cascadeShapeFor(buildSceneGeometry(scene).bounds, s));
  CascadeSet set(*sCtx, scene, layout, s);
  set.runFrame(0.0);
  const SceneGeometry geometry = buildSceneGeometry(scene, 0.0); // the field keeps a reference to it
  const ExactDistanceField exact(geometry);
  for (int i = 0; i < set.levels(); ++i) {
    SCOPED_TRACE("level " + std::to_string(i));
    const SdfPipeline& level = set.level(i);
    EXPECT_EQ(level.fineSpec().voxelSize, 0.6 / 32 * (1 << i));
    EXPECT_EQ(level.settings().band, 0.05 * (1 << i)) << "the band keeps its voxels at every level";
    // Level 0 leaves far instances out; level 1's slack (a quarter of its side, levelSceneSlack) reaches the room's.
    if (i == 0) EXPECT_LT(set.levelScene(i).instances.size(), scene.instances.size()) << "far instances left out";
    // The whole scene on the same grids: the same field, voxel for voxel.
    SdfPipeline whole(*sCtx, scene, layout.levels[std::size_t(i)].grids(), levelSettings(s, i));
    whole.runFrame(0.0);
    EXPECT_EQ(differing(level.coarseField(), whole.coarseField()), 0u);
    EXPECT_EQ(differing(level.fineField(), whole.fineField()), 0u);
    // Under the band the refinement is the exact distance (float rounding).
    const auto grid = level.levelSet(float(level.settings().band));
    const GridSpec& fs = level.fineSpec();
    std::uint64_t voxels = 0;
    double worst = 0.0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      const float d = exact.signedDistance(glm::vec3(fs.indexToWorld(glm::dvec3(c.x(), c.y(), c.z()))));
      worst = std::max(worst, double(std::fabs(std::fabs(*it) - std::fabs(d))) / fs.voxelSize);
      ++voxels;
    }
    EXPECT_GT(voxels, 500u);
    EXPECT_LT(worst, 1e-3) << "fine voxels";
  }
}

// GridShiftPass (one dispatch) leaves every word what gridShiftPlan's copies and fills give on the host (written
// apart from the shader's rule, and checked cell by cell in test_cascade_layout), on grids that are not multiples of
// the work-group shape, cells of one and two words, shifts along each axis, both ways, beyond the grid and none.
TEST_F(CascadeSetGpu, GridShiftPassEqualsThePlansCopiesAndFills) {
  const GridShiftPass pass(*sCtx);
  for (const glm::ivec3 dims : {glm::ivec3(13, 9, 5), glm::ivec3(40, 3, 7)})
    for (const std::uint32_t elementWords : {1u, 2u})
      for (const glm::ivec3 shift : {glm::ivec3(0), glm::ivec3(4, 0, 0), glm::ivec3(-3, 2, 0), glm::ivec3(0, 0, -2),
                                     glm::ivec3(1, -1, 1), glm::ivec3(0, 9, 0), glm::ivec3(-40, 0, 0)}) {
        SCOPED_TRACE(testing::Message() << dims.x << "x" << dims.y << "x" << dims.z << " shift " << shift.x << ","
                                        << shift.y << "," << shift.z << " words " << elementWords);
        std::vector<std::uint32_t> words(std::size_t(dims.x) * dims.y * dims.z * elementWords);
        for (std::size_t i = 0; i < words.size(); ++i) words[i] = gpu::shared::pcgHash(std::uint32_t(i)) | 1u;
        const std::size_t bytes = words.size() * 4;
        const gpu::Buffer buffer(*sCtx, bytes, gpu::kStorage, gpu::Buffer::Memory::Device, "grid");
        const gpu::Buffer scratch(*sCtx, bytes + 64, gpu::kStorage, gpu::Buffer::Memory::Device, "scratch");
        gpu::upload(*sCtx, buffer, words.data(), bytes);
        gpu::CommandBuffer cmd(*sCtx);
        recordGridShift(cmd.handle(), pass, buffer, scratch, gridShiftParams(dims, 4 * elementWords, shift, 0u));
        cmd.submitAndWait();
        std::vector<std::uint32_t> shifted(words.size());
        gpu::download(*sCtx, buffer, shifted.data(), bytes);
        applyGridShift(gridShiftPlan(dims, 4 * elementWords, shift), words, 0u);
        EXPECT_EQ(shifted, words);
      }
  const gpu::Buffer small(*sCtx, 64, gpu::kStorage, gpu::Buffer::Memory::Device, "small");
  gpu::CommandBuffer cmd(*sCtx);
  EXPECT_THROW(recordGridShift(cmd.handle(), pass, small, small, gridShiftParams({4, 4, 4}, 4, {1, 0, 0}, 0u)), Error);
  EXPECT_THROW(gridShiftParams({4, 4, 4}, 6, {0, 0, 0}, 0u), Error);
}

TEST_F(CascadeSetGpu, ACameraMoveScrollsOnlyTheLevelsWhoseBoxMoved) {
  const Scene scene = room();
  const PipelineSettings s = threeLevels();
  const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene).bounds, s);
  ASSERT_EQ(shape.moveCells, 4) << "2 fine voxels a coarse one: a brick of 8 is 4 coarse voxels";
  const double move0 = shape.coarseVoxel(0) * shape.moveCells;
  // Start at a level-2 move lattice point, so that one level-0 move moves no coarser level.
  const glm::dvec3 start = glm::dvec3(0.0, 1.0, 0.0) * shape.coarseVoxel(2) * double(shape.moveCells);
  CascadeSet set(*sCtx, scene, CascadeLayout::around(start, shape), s);
  set.runFrame(0.0);
  EXPECT_TRUE(set.moveTo(start + glm::dvec3(0.3 * move0, 0, 0)).moved.empty()) << "within half a move";
  const glm::dvec3 next = start + glm::dvec3(0.8 * move0, 0, 0); // past half a level-0 move, under half a level-1 one
  const CascadeMove move = set.moveTo(next);
  EXPECT_EQ(move.moved, std::vector<int>{0});
  EXPECT_TRUE(move.rebuilt.empty()) << "one move scrolls";
  set.runFrame(0.0);
  CascadeSet fresh(*sCtx, scene, CascadeLayout::around(next, shape), s);
  fresh.runFrame(0.0);
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE("level " + std::to_string(i));
    EXPECT_EQ(set.level(i).fineSpec().origin, fresh.level(i).fineSpec().origin);
    const double voxel = set.level(i).fineSpec().voxelSize;
    EXPECT_LT(largestDifference(set.level(i).fineField(), fresh.level(i).fineField()) / voxel, 1e-3);
    EXPECT_LT(largestDifference(set.level(i).coarseField(), fresh.level(i).coarseField()) / voxel, 1e-3);
  }
}

// Each level of @a set equals the level of a set built fresh around @a camera at @a time (float rounding aside).
void expectLevelsEqualFresh(const gpu::VulkanContext& ctx, const CascadeSet& set, const Scene& scene,
                            const glm::dvec3& camera, const PipelineSettings& s, double time) {
  CascadeSet fresh(ctx, scene, CascadeLayout::around(camera, set.layout().shape), s);
  fresh.runFrame(time);
  for (int i = 0; i < set.levels(); ++i) {
    SCOPED_TRACE("level " + std::to_string(i));
    ASSERT_EQ(set.level(i).fineSpec().origin, fresh.level(i).fineSpec().origin);
    const double voxel = set.level(i).fineSpec().voxelSize;
    EXPECT_LT(largestDifference(set.level(i).fineField(), fresh.level(i).fineField()) / voxel, 1e-3);
    EXPECT_LT(largestDifference(set.level(i).coarseField(), fresh.level(i).coarseField()) / voxel, 1e-3);
  }
}

// A move whose scroll fails (level 0's, after its shifts are recorded) loses that level and the level after it that
// was to move; the level that was not to move is kept. A lost level is refused, and the next frame builds it again:
// every level then equals a fresh set's. A move whose rebuild fails (a jump past the grids' width) loses the levels
// from it on that were to move; the next move lists them as rebuilt, and they equal a fresh set's.
TEST_F(CascadeSetGpu, AMoveThatFailsLosesTheLevelsItLeftHalfMovedUntilTheyAreBuiltAgain) {
  const Scene scene = room();
  const PipelineSettings s = threeLevels();
  const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene).bounds, s);
  const double move1 = shape.coarseVoxel(1) * shape.moveCells;
  const glm::dvec3 start = glm::dvec3(0.0, 1.0, 0.0) * shape.coarseVoxel(2) * double(shape.moveCells);
  CascadeSet set(*sCtx, scene, CascadeLayout::around(start, shape), s);
  set.runFrame(0.0);
  const glm::dvec3 next = start + glm::dvec3(0.8 * move1, 0, 0); // moves levels 0 and 1, not 2
  const std::vector<glm::i64vec3> shift = CascadeLayout::around(next, shape).shiftSince(set.layout());
  ASSERT_NE(shift[0], glm::i64vec3(0));
  ASSERT_NE(shift[1], glm::i64vec3(0));
  ASSERT_EQ(shift[2], glm::i64vec3(0));
  CascadeFaults(set).failNextScroll(0);
  EXPECT_THROW(set.moveTo(next), Error);
  EXPECT_THROW(set.level(0), Error);
  EXPECT_THROW(set.levelScene(1), Error);
  EXPECT_NO_THROW(set.level(2)) << "a level that was not to move is kept";
  set.runFrame(1 / 30.0);
  expectLevelsEqualFresh(*sCtx, set, scene, next, s, 1 / 30.0);

  const glm::dvec3 far = next + glm::dvec3(2.5, 0, 0);
  const std::vector<glm::i64vec3> jump = CascadeLayout::around(far, shape).shiftSince(set.layout());
  std::vector<int> lost;
  for (int i = 0; i < set.levels(); ++i)
    if (jump[std::size_t(i)] != glm::i64vec3(0)) lost.push_back(i);
  ASSERT_FALSE(lost.empty());
  ASSERT_EQ(lost[0], 0);
  CascadeFaults(set).failNextBuild();
  EXPECT_THROW(set.moveTo(far), Error);
  for (int i : lost) EXPECT_THROW(set.level(i), Error) << "level " << i;
  const CascadeMove again = set.moveTo(far);
  EXPECT_TRUE(again.moved.empty()) << "the layout is already there";
  EXPECT_EQ(again.rebuilt, lost);
  set.runFrame(2 / 30.0);
  expectLevelsEqualFresh(*sCtx, set, scene, far, s, 2 / 30.0);
}

// A camera walking, then driving, along a diagonal that also climbs and turns back, while the teapot orbits: after
// every frame each level equals levels built fresh there and then (float rounding: a scrolled level measures from
// its new corner), every move scrolls (the scene cut again once a level drifts past its slack, no level rebuilt),
// and the scrolled levels refine far fewer voxels than fresh ones.
TEST_F(CascadeSetGpu, ScrolledLevelsAlongACameraPathEqualLevelsBuiltFresh) {
  const Scene scene = room();
  PipelineSettings s = threeLevels();
  s.coarseRes = 32;
  s.fineRes = 64;
  const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene).bounds, s);
  glm::dvec3 camera(-0.5, 0.3, -0.4);
  CascadeSet set(*sCtx, scene, CascadeLayout::around(camera, shape), s);
  set.runFrame(0.0);
  int scrolls = 0, recuts = 0, rebuilds = 0;
  std::uint64_t scrolledRefined = 0, freshRefined = 0, scrolledVoxelized = 0, freshVoxelized = 0;
  std::uint64_t scrolledRebuilt = 0, freshRebuilt = 0, scrolledUpsampled = 0, freshUpsampled = 0;
  std::uint64_t scrolledMasked = 0, freshMasked = 0;
  int maskedOverBlocks = 0;
  double worst = 0.0;
  for (int f = 1; f <= 14; ++f) {
    const double speed = f < 8 ? 0.03 : 0.09;
    camera += speed * glm::dvec3(1.0, f % 5 == 0 ? -0.5 : 0.25, f < 11 ? 0.8 : -1.2);
    const CascadeMove move = set.moveTo(camera);
    rebuilds += int(move.rebuilt.size());
    recuts += int(move.recut.size());
    scrolls += int(move.moved.size() - move.rebuilt.size());
    const double t = f / 30.0;
    const std::vector<FrameStats> stats = set.runFrame(t);
    CascadeSet fresh(*sCtx, scene, CascadeLayout::around(camera, shape), s);
    const std::vector<FrameStats> freshStats = fresh.runFrame(t);
    for (int i = 0; i < set.levels(); ++i) {
      SCOPED_TRACE("frame " + std::to_string(f) + ", level " + std::to_string(i));
      ASSERT_EQ(set.level(i).fineSpec().origin, fresh.level(i).fineSpec().origin);
      const double voxel = set.level(i).fineSpec().voxelSize;
      const double fine = largestDifference(set.level(i).fineField(), fresh.level(i).fineField()) / voxel;
      const double coarse = largestDifference(set.level(i).coarseField(), fresh.level(i).coarseField()) / voxel;
      EXPECT_LT(fine, 1e-3);
      EXPECT_EQ(differing(set.level(i).coarseField(), fresh.level(i).coarseField()), 0u) << "coarse voxels";
      worst = std::max({worst, fine, coarse});
      // The seeds a scroll kept and those voxelized where the level entered are a full build's, bit for bit.
      EXPECT_EQ(PipelineProbe(set.level(i)).coarseSeeds(), PipelineProbe(fresh.level(i)).coarseSeeds());
      // The band's counts and bricks, carried over the scroll and changed where the mask visited, are a fresh count's.
      const FrameStats &a = stats[std::size_t(i)], &b = freshStats[std::size_t(i)];
      EXPECT_EQ(a.maskCoarseVoxels, b.maskCoarseVoxels);
      EXPECT_EQ(a.maskFineVoxels, b.maskFineVoxels);
      EXPECT_EQ(a.activeBricks, b.activeBricks);
      const bool scrolled = std::count(move.moved.begin(), move.moved.end(), i) &&
                            !std::count(move.rebuilt.begin(), move.rebuilt.end(), i);
      if (scrolled) {
        EXPECT_LE(stats[std::size_t(i)].refinedFineVoxels, freshStats[std::size_t(i)].refinedFineVoxels);
        scrolledRefined += stats[std::size_t(i)].refinedFineVoxels;
        freshRefined += freshStats[std::size_t(i)].refinedFineVoxels;
      }
      if (scrolled && !std::count(move.recut.begin(), move.recut.end(), i)) {
        scrolledVoxelized += stats[std::size_t(i)].coarseVoxelizedVoxels;
        freshVoxelized += freshStats[std::size_t(i)].coarseVoxelizedVoxels;
        scrolledRebuilt += stats[std::size_t(i)].coarseRebuiltVoxels;
        freshRebuilt += freshStats[std::size_t(i)].coarseRebuiltVoxels;
        scrolledUpsampled += stats[std::size_t(i)].upsampledFineVoxels;
        freshUpsampled += freshStats[std::size_t(i)].upsampledFineVoxels;
        scrolledMasked += a.maskVisitedVoxels;
        freshMasked += b.maskVisitedVoxels;
        maskedOverBlocks += a.maskVisitedVoxels < set.level(i).coarseSpec().voxelCount();
      }
    }
  }
  EXPECT_GE(scrolls, 8);
  EXPECT_EQ(rebuilds, 0);
  EXPECT_GE(recuts, 1) << "the driving camera drifts past level 0's slack";
  // Only what entered is refined (the moving teapot's reach aside), and voxelized where the scene was not cut again.
  EXPECT_LT(double(scrolledRefined), 0.5 * double(freshRefined));
  EXPECT_LT(double(scrolledVoxelized), 0.5 * double(freshVoxelized));
  EXPECT_LT(scrolledRebuilt, freshRebuilt) << "the transform over what the seeds that entered and left reach";
  EXPECT_LT(double(scrolledUpsampled), 0.8 * double(freshUpsampled))
      << "the upsampling over the blocks that what changed, entered and the faces left behind reach";
  EXPECT_GE(maskedOverBlocks, 4) << "scrolled levels' masks over the blocks of what changed";
  EXPECT_LT(double(scrolledMasked), 0.8 * double(freshMasked))
      << "the mask over the blocks that what changed, entered, settles or moves reaches";
  std::printf("%d scrolls (%d with the scene cut again), %d rebuilds; largest difference from fresh levels %.2e fine "
              "voxels; scrolled levels refined %.3f of the voxels fresh ones did, voxelized %.3f, transformed "
              "%.3f, upsampled %.3f and masked %.3f (%d masks over blocks)\n",
              scrolls, recuts, rebuilds, worst, double(scrolledRefined) / double(freshRefined),
              double(scrolledVoxelized) / double(freshVoxelized), double(scrolledRebuilt) / double(freshRebuilt),
              double(scrolledUpsampled) / double(freshUpsampled), double(scrolledMasked) / double(freshMasked),
              maskedOverBlocks);
}

// A run of the mask over what changed after a scroll reads the last run's settling box as the scroll left it: moved
// with its voxels, clipped to the grid, empty where all of it left (the camera-path test's levels settle at once).
TEST(MaskScroll, SettlingBoxesMoveWithTheirVoxelsAndAreEmptyWhereAllLeft) {
  using gpu::shared::MaskRegion;
  const glm::ivec3 dims(16, 16, 16);
  MaskRegion r{};
  r.settlingLo[0] = glm::uvec4(2, 3, 4, 0);
  r.settlingHi[0] = glm::uvec4(10, 12, 14, 0);
  r.settlingLo[1] = glm::uvec4(0xFFFFFFFFu);
  r.settlingHi[1] = glm::uvec4(0u);
  MaskRegion m = settlingMovedWith(r, dims, glm::ivec3(4, 0, -2));
  EXPECT_EQ(glm::uvec3(m.settlingLo[0]), glm::uvec3(0, 3, 6));
  EXPECT_EQ(glm::uvec3(m.settlingHi[0]), glm::uvec3(6, 12, 15));
  EXPECT_EQ(m.settlingLo[1], glm::uvec4(0xFFFFFFFFu)) << "an empty box stays empty";
  m = settlingMovedWith(r, dims, glm::ivec3(-8, 0, 0));
  EXPECT_EQ(glm::uvec3(m.settlingLo[0]), glm::uvec3(10, 3, 4));
  EXPECT_EQ(glm::uvec3(m.settlingHi[0]), glm::uvec3(15, 12, 14));
  for (const glm::ivec3 shift : {glm::ivec3(11, 0, 0), glm::ivec3(0, -13, 0), glm::ivec3(0, 0, 15)}) {
    m = settlingMovedWith(r, dims, shift);
    EXPECT_EQ(m.settlingLo[0], glm::uvec4(0xFFFFFFFFu)) << "all of it left";
    EXPECT_EQ(m.settlingHi[0], glm::uvec4(0u));
  }
}

// Kept sparse (only the bricks on the GPU, no dense fine SDF), a scrolled level keeps its bricks' values in their
// slots and frees the slots of the bricks that left: after moves along every axis both ways, the field resolved from
// the bricks equals a fresh level's, and the pool never regrows.
TEST_F(CascadeSetGpu, ScrolledSparseLevelsKeepTheirBricks) {
  const Scene scene = room();
  PipelineSettings s = threeLevels();
  s.fineStorage = FineStorage::Sparse;
  s.cascades = 2;
  const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene).bounds, s);
  const double move = shape.coarseVoxel(0) * shape.moveCells;
  glm::dvec3 camera(-0.3, 0.45, 0.1);
  CascadeSet set(*sCtx, scene, CascadeLayout::around(camera, shape), s);
  set.runFrame(0.0);
  const std::uint64_t pool = set.level(0).poolBricks();
  // Back and forth over the room's corner: slots that leaked would run the pool out (it holds half as many again).
  std::vector<glm::dvec3> steps = {glm::dvec3(0, -1, 1), glm::dvec3(0, 1, -1)};
  for (int k = 0; k < 6; ++k) steps.push_back(glm::dvec3(k % 2 ? 2 : -2, 0, 0));
  for (const glm::dvec3& step : steps) {
    camera += step * move;
    const CascadeMove moved = set.moveTo(camera);
    EXPECT_TRUE(std::count(moved.moved.begin(), moved.moved.end(), 0)) << "level 0 moves";
    EXPECT_TRUE(moved.rebuilt.empty());
    set.runFrame(0.0);
    CascadeSet fresh(*sCtx, scene, CascadeLayout::around(camera, shape), s);
    fresh.runFrame(0.0);
    for (int i = 0; i < 2; ++i)
      EXPECT_LT(largestDifference(set.level(i).fineField(), fresh.level(i).fineField()) / set.level(i).fineSpec().voxelSize,
                1e-3) << i;
  }
  EXPECT_EQ(set.level(0).poolBricks(), pool) << "the slots of the bricks that left were freed";
}

// The orbiting teapot moves every frame; a level whose box and reach it never meets skips its coarse passes and
// its refinement (the teapot's motion counts only near a grid: InstanceMotion's reach), the level holding the
// teapot runs them, and after the frames every level equals levels built fresh at the last frame's time.
TEST_F(CascadeSetGpu, AnInstanceMovingFarFromALevelLeavesItsPassesAlone) {
  const Scene scene = room();
  const PipelineSettings s = threeLevels();
  const CascadeShape shape = cascadeShapeFor(buildSceneGeometry(scene).bounds, s);
  const glm::dvec3 camera(-0.6, 1.0, -0.6); // level 0 (0.6 wide) in the far corner from the teapot's orbit
  CascadeSet set(*sCtx, scene, CascadeLayout::around(camera, shape), s);
  set.runFrame(0.0);
  std::vector<FrameStats> last;
  for (int f = 1; f <= 3; ++f) last = set.runFrame(f / 30.0);
  EXPECT_EQ(last[0].movedInstances, 0u);
  EXPECT_TRUE(last[0].skipped("VoxelizePass"));
  EXPECT_EQ(last[0].refinedFineVoxels, 0u);
  EXPECT_EQ(last[2].movedInstances, 1u) << "the outermost level holds the room and its teapot";
  EXPECT_FALSE(last[2].skipped("VoxelizePass"));
  EXPECT_GT(last[2].refinedFineVoxels, 0u);
  CascadeSet fresh(*sCtx, scene, CascadeLayout::around(camera, shape), s);
  fresh.runFrame(3 / 30.0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(differing(set.level(i).fineField(), fresh.level(i).fineField()), 0u) << i;
}

TEST_F(CascadeSetGpu, APipelineIsOneBox) {
  const Scene scene = room();
  PipelineSettings s = threeLevels();
  try {
    SdfPipeline pipe(*sCtx, scene, buildSceneGeometry(scene).bounds, s);
    FAIL() << "a pipeline of 3 cascades";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.setting(), "cascades");
  }
}

TEST(CascadeBake, WritesOneLevelSetPerLevelThatCompareChecksOnItsOwnVoxels) {
  test::TempDir dir;
  // A floor, a wall and a ball, the camera among them (levels are centred on it).
  test::writeText(dir / "corner.json", R"({"meshes": {"floor": {"box": [2, 0.04, 2]}, "wall": {"box": [0.04, 1, 2]},
    "ball": {"sphere": {"radius": 0.2}}},
    "instances": [{"mesh": "floor", "translate": [0, -0.02, 0]}, {"mesh": "wall", "translate": [-0.5, 0.5, 0]},
                  {"mesh": "ball", "translate": [0.2, 0.2, 0]}],
    "camera": {"position": [0.1, 0.3, 0.3], "look_at": [0, 0, 0]}})");
  BakeOptions o;
  o.scene = (dir / "corner.json").string();
  o.method = BakeMethod::Rtsdf;
  o.pipeline = threeLevels();
  o.frames = 1;
  const BakeResult r = bake(o);
  ASSERT_EQ(r.levels.size(), 3u);
  writeBake(r, dir / "levels.vdb");
  const std::vector<openvdb::FloatGrid::Ptr> levels = cascadeLevelGrids(readVdb(dir / "levels.vdb"));
  ASSERT_EQ(levels.size(), 3u);
  const Scene scene = loadScene(dir / "corner.json");
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(levels[std::size_t(i)]->getName(), "surface_L" + std::to_string(i));
    const GridSpec spec = gridSpecOf(*levels[std::size_t(i)]);
    EXPECT_DOUBLE_EQ(spec.voxelSize, 0.6 / 32 * (1 << i));
    EXPECT_EQ(levels[std::size_t(i)]->metaValue<int>("rtsdf:cascade_level"), i);
    EXPECT_GT(levels[std::size_t(i)]->activeVoxelCount(), 0u);
    // Centred on the scene camera, to half a move (4 coarse voxels of 2 fine ones: a brick) along each axis.
    const glm::dvec3 cam = scene.cameraAt(0.0).position;
    EXPECT_LE(glm::length(spec.bounds().center() - cam), std::sqrt(3.0) * 0.5 * spec.voxelSize * 2 * 4);
  }
  EXPECT_THROW(readLevelSet(dir / "levels.vdb"), Error) << "no single 'surface' grid";
  CompareOptions c;
  c.a = dir / "levels.vdb";
  c.against = CompareAnchor::Exact;
  const FileComparison cmp = compare(c);
  ASSERT_EQ(cmp.levels.size(), 3u);
  for (const FileComparison& level : cmp.levels) {
    EXPECT_GT(level.error.voxels, 100u) << level.nameA;
    EXPECT_LT(level.error.meanAbs, 0.01) << level.nameA;
    EXPECT_LT(level.error.signErrorRate(), 0.01) << level.nameA;
  }
  EXPECT_NE(cmp.report().find("cascade level 2"), std::string::npos);
  // Two files: levels are compared against an anchor only.
  CompareOptions two;
  two.a = c.a;
  two.b = c.a;
  EXPECT_THROW(compare(two), SettingError);
  // Cascades are an rtsdf bake.
  o.method = BakeMethod::Exact;
  EXPECT_THROW(bake(o), SettingError);
}

// Four levels of level 0 6.25 m wide around the camera of the same town generated at 50, 200 and 1000 m, after their
// first frame. The estimate the set checks before allocating (CascadeSet::memory, with the pools the frame sized) is
// the allocation to within -1%..+2% at coarse 64 / fine 128 (where the town's triangles weigh most: counting every
// instance's triangles in the BVH, as the estimate did before, is 2.8% over at 200 m and 5.1% at 1000 m) and at 64 /
// 256; at 64 /
// 256 (level 0: 2.4 cm voxels) the device memory the levels hold as allocated (buffers and textures, the brick pools
// as the first frame sized them, each level's part of the town) moves less than 5% between the towns.
TEST_F(CascadeSetGpu, AllocatedMemoryStaysWithin5PercentFrom50To1000MetresAndIsTheEstimate) {
  test::TempDir dir;
  PipelineSettings s;
  s.coarseRes = 64;
  s.mode = RefineMode::Closest;
  s.rays = 0;
  s.cascades = 4;
  s.cascadeExtent = 6.25;
  // The bytes the levels hold after their first frame at fine resolution @a fine, the estimate checked against them.
  const auto allocatedBy = [&](const Scene& town, int fine) {
    s.fineRes = fine;
    const std::uint64_t before = sCtx->deviceBytesInUse();
    const glm::dvec3 camera = town.cameraAt(0.0).position;
    CascadeSet set(*sCtx, town,
                   CascadeLayout::around(camera, cascadeShapeFor(buildSceneGeometry(town).bounds, camera, s)), s);
    const FrameStats frame = sumFrameStats(set.runFrame(0.0));
    EXPECT_EQ(frame.overflowBricks, 0u);
    const double held = double(sCtx->deviceBytesInUse() - before);
    // The levels' estimates with the pools sized (FrameStats::deviceBytes) and the scratch the levels share.
    const double estimate = double(frame.deviceBytes + set.memory().scrollScratchBytes);
    // It bounds the BVH's nodes by two per triangle, so it may lie a little above, never much below.
    EXPECT_GT(estimate / held, 0.99) << "fine " << fine << ": estimate " << estimate << ", allocated " << held;
    EXPECT_LT(estimate / held, 1.02) << "fine " << fine << ": estimate " << estimate << ", allocated " << held;
    std::printf("fine %d: %.2f MiB allocated, %.2f MiB estimated, %llu pool bricks\n", fine, held / 1048576.0,
                estimate / 1048576.0, (unsigned long long)frame.poolBricks);
    return held;
  };
  std::vector<double> allocated;
  for (const int size : {50, 200, 1000}) {
    std::string log;
    const std::string level = test::makeLevel((dir / std::to_string(size)).string(), size, log);
    ASSERT_FALSE(level.empty()) << log;
    const Scene town = loadScene(level);
    std::printf("%d m\n", size);
    if (size == 50) allocatedBy(town, 128); // the estimate at a second fine resolution: one town is enough
    allocated.push_back(allocatedBy(town, 256));
  }
  for (std::size_t i = 1; i < allocated.size(); ++i)
    EXPECT_LT(std::abs(allocated[i] - allocated[0]), 0.05 * allocated[0]) << i;
}
