// A frame runs only the passes whose inputs changed (planFrame): frame by frame the same coarse SDF, band, bricks and
// fine field as a pipeline that rebuilds every pass (PipelineSettings::fullRebuild), and the skipped passes are
// neither recorded nor timed.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/mask/MaskParams.h"
#include "sdf/mask/MaskPasses.h"
#include "sdf/pipeline/InstanceMotion.h"
#include "sdf/pipeline/PipelineProbe.h"
#include "sdf/refine/RefineCpu.h"
#include "sdf/refine/RefinePasses.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace rtsdf;

namespace {

struct FramePassesTag : test::NoSuiteObjects {};
using FramePasses = test::VulkanSuite<FramePassesTag>;

constexpr double kFps = 30.0;

/// Frame times that move, stand still for several frames (the same moment again), then move again.
const std::vector<double> kMovingThenStill = {0, 1 / kFps, 2 / kFps, 2 / kFps, 2 / kFps, 2 / kFps, 3 / kFps, 4 / kFps,
                                              4 / kFps};
const std::vector<double> kStill(6, 0.0);

std::size_t differing(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
  return n;
}

/// Per brick: whether it holds a slot.
std::vector<bool> slotted(const std::vector<std::uint32_t>& slots) {
  std::vector<bool> out(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) out[i] = slots[i] != gpu::shared::kNoBrick;
  return out;
}

/// Runs @a times through a pipeline with @a s and one that rebuilds every pass, comparing them bit for bit after each
/// frame; returns the number of frames the first skipped the coarse SDF in.
int expectEqualToAFullRebuild(const gpu::VulkanContext& ctx, const Scene& scene, const std::string& scenePath,
                              PipelineSettings s, const std::vector<double>& times) {
  Bounds bounds;
  for (const double t : times) bounds.add(buildSceneGeometry(scene, t).bounds);
  SdfPipeline skipping(ctx, scene, bounds, s);
  s.fullRebuild = true;
  SdfPipeline rebuilt(ctx, scene, bounds, s);
  const PipelineProbe ps(skipping), pr(rebuilt);
  int coarseSkipped = 0;
  for (std::size_t f = 0; f < times.size(); ++f) {
    SCOPED_TRACE(::testing::Message() << scenePath << ", frame " << f + 1 << " at " << times[f] << " s");
    const FrameStats a = skipping.runFrame(times[f]), b = rebuilt.runFrame(times[f]);
    EXPECT_TRUE(b.skippedPasses.empty());
    coarseSkipped += a.skipped(VoxelizePass::kName);
    EXPECT_EQ(a.maskFineVoxels, b.maskFineVoxels);
    EXPECT_EQ(a.maskCoarseVoxels, b.maskCoarseVoxels);
    EXPECT_EQ(a.refinedFineVoxels, b.refinedFineVoxels);
    EXPECT_EQ(a.activeBricks, b.activeBricks);
    EXPECT_EQ(differing(skipping.coarseField(), rebuilt.coarseField()), 0u) << "coarse voxels differ";
    EXPECT_EQ(skipping.rayMask().fineVoxels, rebuilt.rayMask().fineVoxels);
    EXPECT_EQ(ps.refinedVoxels(), pr.refinedVoxels());
    EXPECT_EQ(ps.movedOnlyCoarse(), pr.movedOnlyCoarse());
    EXPECT_EQ(a.movedKeptVoxels, b.movedKeptVoxels);
    EXPECT_EQ(slotted(ps.brickSlots()), slotted(pr.brickSlots())); // which slot is the order of atomics
    EXPECT_EQ(differing(skipping.fineField(), rebuilt.fineField()), 0u) << "fine voxels differ";
  }
  return coarseSkipped;
}

int expectEqualToAFullRebuild(const gpu::VulkanContext& ctx, const std::string& scenePath, PipelineSettings s,
                              const std::vector<double>& times) {
  return expectEqualToAFullRebuild(ctx, loadScene(test::dataPath(scenePath)), scenePath, s, times);
}

PipelineSettings closestAt(int coarse, int fine, int rays) {
  PipelineSettings s = test::formerPipelineDefaults();
  s.coarseRes = coarse;
  s.fineRes = fine;
  s.mode = RefineMode::Closest;
  s.rays = rays;
  return s;
}

/// A block crossing a floor 8 long at 30 m/s (1 m a frame at 30 fps, for 0.2 s), written into @a dir and loaded.
Scene crossingBlock(const test::TempDir& dir) {
  test::writeText(dir / "crossing.json", R"({"rtsdf_scene": 1,
    "meshes": {"floor": {"box": [8, 0.2, 3]}, "block": {"box": [1, 0.6, 0.6]}},
    "instances": [{"name": "floor", "mesh": "floor", "translate": [0, -0.1, 0]},
      {"name": "block", "mesh": "block", "animation": {"keyframes": [
        {"time": 0, "translate": [-3, 0.35, 0]}, {"time": 0.2, "translate": [3, 0.35, 0]}]}}]})");
  return loadScene(dir / "crossing.json");
}

bool timed(const FrameStats& st, const std::string& pass) {
  for (const auto& entry : st.passMs)
    if (entry.first == pass) return true;
  return false;
}

} // namespace

// The orbiting teapot of the default scene, moving, standing still for three frames, moving again: closest mode with
// the exact sign (settles in one refinement) and with sign rays (four), rays mode (refreshed every frame, so the mask
// never stops), dense and sparse.
TEST_F(FramePasses, SkippingFramesEqualAFullRebuildOnTheOrbitingTeapot) {
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/default.json", closestAt(40, 80, 0), kMovingThenStill), 4);
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/default.json", closestAt(32, 64, 1), kMovingThenStill), 4);
  PipelineSettings sparse = closestAt(32, 64, 0);
  sparse.fineStorage = FineStorage::Sparse;
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/default.json", sparse, kMovingThenStill), 4);
  PipelineSettings rays = test::formerPipelineDefaults();
  rays.coarseRes = 24;
  rays.fineRes = 48;
  rays.rays = 2;
  rays.settleFrames = 2;
  rays.refreshPeriod = 3;
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/default.json", rays, kMovingThenStill), 4);
}

// A block crossing a floor at 1 m a frame leaves whole bricks behind it each frame: a run of the mask over what
// changed must give their slots back (their band counts fall to zero), as a full rebuild does.
TEST_F(FramePasses, SkippingFramesEqualAFullRebuildWhereAnInstanceLeavesBricks) {
  const test::TempDir dir;
  std::vector<double> times;
  for (int f = 0; f < 6; ++f) times.push_back(f / kFps);
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, crossingBlock(dir), "crossing.json", closestAt(64, 128, 0), times), 0);
}

// A static scene: after the first frame nothing moves, so only the settling refinements run.
TEST_F(FramePasses, SkippingFramesEqualAFullRebuildOnAStaticScene) {
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/bunny.json", closestAt(32, 64, 1), kStill), 5);
  EXPECT_EQ(expectEqualToAFullRebuild(*sCtx, "scenes/default.json", closestAt(32, 64, 0), kStill), 5);
}

// The passes a frame skips are neither recorded nor timed, and say so in FrameStats; the full rebuild runs them all.
// Closest mode with the exact sign on a static scene: frame 1 runs everything, frame 2 only the mask (it listed the
// band last time), frame 3 nothing; a moving frame runs everything again.
TEST_F(FramePasses, AStaticFrameRunsNoPassAndAMovingOneRunsThemAll) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  Bounds bounds;
  for (int f = 0; f < 2; ++f) bounds.add(buildSceneGeometry(scene, f / kFps).bounds);
  const std::vector<std::string> coarse = {VoxelizePass::kName, ExactEdtPass::kName, CoarseDistancePass::kName};
  const std::vector<std::string> mask = {MaskCompactPass::kName, BrickAllocPass::kName, MaskDispatchPass::kName,
                                         ClosestRefinePass::kName};
  for (const bool fullRebuild : {false, true}) {
    SCOPED_TRACE(fullRebuild ? "full rebuild" : "skipping");
    PipelineSettings s = closestAt(32, 64, 0);
    s.fullRebuild = fullRebuild;
    SdfPipeline pipe(*sCtx, scene, bounds, s);
    const std::vector<FrameStats> st = {pipe.runFrame(0.0), pipe.runFrame(0.0), pipe.runFrame(0.0),
                                        pipe.runFrame(1 / kFps)};
    for (std::size_t f = 0; f < st.size(); ++f) {
      SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
      const bool coarseRuns = fullRebuild || f == 0 || f == 3, maskRuns = coarseRuns || f == 1;
      for (const std::string& pass : coarse) {
        EXPECT_EQ(timed(st[f], pass), coarseRuns) << pass;
        EXPECT_EQ(st[f].skipped(pass), !coarseRuns) << pass;
      }
      for (const std::string& pass : mask) {
        EXPECT_EQ(timed(st[f], pass), maskRuns) << pass;
        EXPECT_EQ(st[f].skipped(pass), !maskRuns) << pass;
      }
      EXPECT_EQ(timed(st[f], UpsamplePass::kName), coarseRuns);
      EXPECT_EQ(st[f].skipped(UpsamplePass::kName), !coarseRuns);
      EXPECT_EQ(st[f].fieldChanged, maskRuns);
      EXPECT_GT(st[f].maskFineVoxels, 0u);
    }
    EXPECT_EQ(st[2].refinedFineVoxels, 0u);
    EXPECT_EQ(st[1].maskFineVoxels, st[2].maskFineVoxels);
    EXPECT_GT(st[3].refinedFineVoxels, 0u);
  }
}

// When only an instance moved, CoarseDistancePass's changed box is the box of the coarse voxels whose value differs
// from the last build's (against the two fields read back), and the upsampling covers the fine voxels near it only:
// the orbiting teapot of the default scene changes a corner of the room. (That the result equals a whole-grid
// upsampling bit for bit is SkippingFramesEqualAFullRebuildOnTheOrbitingTeapot's: with the region not grown by the
// cells' reach it fails.)
TEST_F(FramePasses, AMovingInstanceUpsamplesOnlyWhereTheCoarseSdfChanged) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  Bounds bounds;
  for (int f = 0; f < 3; ++f) bounds.add(buildSceneGeometry(scene, f / kFps).bounds);
  SdfPipeline pipe(*sCtx, scene, bounds, closestAt(48, 96, 0));
  const std::uint64_t all = pipe.fineSpec().voxelCount();
  EXPECT_EQ(pipe.runFrame(0.0).upsampledFineVoxels, all) << "the first frame upsamples every voxel";
  for (int f = 1; f < 3; ++f) {
    SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
    const std::vector<float> before = pipe.coarseField();
    const FrameStats st = pipe.runFrame(f / kFps);
    const std::vector<float> after = pipe.coarseField();
    const glm::ivec3 dims = pipe.coarseSpec().dims;
    glm::uvec3 lo(~0u), hi(0u);
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          const std::size_t i = (std::size_t(z) * dims.y + y) * dims.x + x;
          if (std::memcmp(&before[i], &after[i], 4) == 0) continue;
          lo = glm::min(lo, glm::uvec3(x, y, z));
          hi = glm::max(hi, glm::uvec3(x, y, z));
        }
    ASSERT_LE(lo.x, hi.x) << "the teapot moved: some coarse voxels changed";
    const gpu::shared::ChangedBox box = pipe.changedCoarseBox();
    EXPECT_EQ(glm::uvec3(box.lo), lo);
    EXPECT_EQ(glm::uvec3(box.hi), hi);
    EXPECT_GT(st.upsampledFineVoxels, 0u);
    EXPECT_LT(st.upsampledFineVoxels, all / 2) << "the teapot changes a corner of the room";
    // The blocks marked, and those listed for the upsampling, are the CPU copies' on the two fields; their fine
    // voxels are the count.
    const PipelineProbe probe(pipe);
    const std::vector<std::uint32_t> marks = probe.changedCoarseBlocks();
    EXPECT_EQ(marks, changedBlockMarksCpu(before, after, dims));
    const std::vector<std::uint32_t> listed = probe.upsampledBlocks();
    EXPECT_EQ(listed, upsampleBlocksCpu(marks, dims, gpu::shared::UpsampleBoxes{}));
    const glm::dvec3 corner = pipe.fineSpec().origin; // the frame the pipeline measures from
    const std::vector<int> begins =
        upsampleBlockFineBegins(pipe.coarseSpec().inFrame(corner), pipe.fineSpec().inFrame(corner));
    const glm::ivec3 bd = gpu::shared::coarseBlockDims(dims);
    std::uint64_t listedFine = 0;
    for (const std::uint32_t b : listed) {
      const glm::ivec3 c = gpu::shared::linearCell(b, bd);
      std::uint64_t n = 1;
      for (int a = 0; a < 3; ++a) {
        const int at = gpu::shared::upsampleBlockFineAt(bd, a) + c[a];
        n *= std::uint64_t(begins[std::size_t(at + 1)] - begins[std::size_t(at)]);
      }
      listedFine += n;
    }
    EXPECT_EQ(st.upsampledFineVoxels, listedFine);
    std::printf("frame %d: coarse box (%u %u %u)-(%u %u %u) of %dx%dx%d, upsampled %.1f%% of the fine voxels\n", f + 1,
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, dims.x, dims.y, dims.z, 100.0 * double(st.upsampledFineVoxels) / double(all));
  }
}

// Where only an instance moved, the coarse SDF is built over what its seeds can reach: the seeds are voxelized in the
// moved boxes' seed box alone; the region CoarseRegionPass gives is its CPU copy's on the block bounds before the frame
// and that box, holds every coarse voxel whose value changed (against the two fields read back) and is a part of the
// grid; every voxel's bound of its squared seed distance holds. (That the field equals a full build bit for bit is
// SkippingFramesEqualAFullRebuildOnTheOrbitingTeapot's; a region too small fails CoarseSdfGpu's
// ExactEdtOverAChangeEqualsBruteForce, a box voxelized wrong its
// ABuildOverAChangeVoxelizesItsBoxAloneAndEqualsAFullBuild.)
TEST_F(FramePasses, AMovingInstanceRebuildsTheCoarseSdfOnlyWhereItsSeedsReach) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  Bounds bounds;
  for (int f = 0; f < 4; ++f) bounds.add(buildSceneGeometry(scene, f / kFps).bounds);
  SdfPipeline pipe(*sCtx, scene, bounds, closestAt(64, 128, 0));
  const PipelineProbe probe(pipe);
  const glm::ivec3 dims = pipe.coarseSpec().dims;
  const std::uint64_t all = pipe.coarseSpec().voxelCount();
  const FrameStats first = pipe.runFrame(0.0);
  EXPECT_EQ(first.coarseRebuiltVoxels, all) << "the first frame builds the whole grid";
  EXPECT_EQ(first.coarseVoxelizedVoxels, all);
  EXPECT_FALSE(probe.coarseOverChange());
  for (int f = 1; f < 4; ++f) {
    SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
    const std::vector<std::uint32_t> blockMax = probe.coarseBlockMax();
    const std::vector<float> before = pipe.coarseField();
    const FrameStats st = pipe.runFrame(f / kFps);
    const std::vector<float> after = pipe.coarseField();
    ASSERT_TRUE(probe.coarseOverChange());
    const CoarseRegionLists region = probe.coarseRegion();
    const CoarseVoxelBox change = movedSeedBox(probe.lastMovedBoxes(), pipe.coarseSpec().inFrame(pipe.frameOrigin()));
    ASSERT_FALSE(change.empty());
    const CoarseRegionLists cpu = coarseRegionCpu(blockMax, dims, change);
    EXPECT_EQ(region.blocks, cpu.blocks);
    EXPECT_EQ(region.columns, cpu.columns);
    EXPECT_EQ(region.voxels, cpu.voxels);
    EXPECT_EQ(st.coarseRebuiltVoxels, cpu.voxels);
    EXPECT_EQ(st.coarseVoxelizedVoxels, regionVoxels(change)) << "the seeds are voxelized in the moved boxes alone";
    EXPECT_LT(st.coarseRebuiltVoxels, all / 2) << "the teapot reaches a part of the room";
    const glm::ivec3 bd = gpu::shared::coarseBlockDims(dims);
    std::vector<bool> listed(std::size_t(bd.x) * bd.y * bd.z, false);
    for (std::uint32_t b : cpu.blocks) listed[b] = true;
    std::size_t changed = 0, outside = 0;
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          const std::size_t i = (std::size_t(z) * dims.y + y) * dims.x + x;
          if (std::memcmp(&before[i], &after[i], 4) == 0) continue;
          ++changed;
          outside += !listed[gpu::shared::coarseBlockIndex(glm::ivec3(x, y, z), bd)];
        }
    EXPECT_GT(changed, 0u);
    EXPECT_EQ(outside, 0u) << "coarse voxels changed outside the region's blocks";
    // The bounds after the frame: at least each voxel's squared distance to its nearest seed, in voxels.
    const std::vector<std::uint32_t> bounds = probe.coarseBlockMax();
    const GridSpec& cs = pipe.coarseSpec();
    const double beta = pipe.settings().beta >= 0.0 ? pipe.settings().beta : 0.5 * cs.voxelSize;
    std::size_t below = 0;
    for (std::size_t i = 0; i < after.size(); ++i) {
      const glm::ivec3 v(int(i % dims.x), int(i / dims.x % dims.y), int(i / dims.x / dims.y));
      const double d = (double(after[i]) + beta) / cs.voxelSize;
      below += double(bounds[gpu::shared::coarseBlockIndex(v, gpu::shared::coarseBlockDims(dims))]) < d * d * 0.999;
    }
    EXPECT_EQ(below, 0u) << "voxels farther from their seed than their block's bound";
    std::printf("frame %d: %zu coarse voxels changed; built over %.1f%% of the grid\n", f + 1, changed,
                100.0 * double(st.coarseRebuiltVoxels) / double(all));
  }
}

// Where only an instance moved, the mask visits the coarse voxels whose decisions can change (MaskRegionPass): the box
// of those whose coarse value changed, those the teapot's swept box comes within the band's reach of, and the band
// voxels the last run left settling (from the state read back before the frame: in the band, fewer refinements than
// settleFrames). Sign rays (settling over four runs) and a frame standing still (the mask runs for the settling
// voxels alone). That the fields, bricks and counts equal a full rebuild's is
// SkippingFramesEqualAFullRebuildOnTheOrbitingTeapot's; that the decisions equal the CPU copy's over the same box is
// Refine.IncrementalDecisionsEqualTheCpuReference's.
TEST_F(FramePasses, AMovingInstanceVisitsOnlyTheMaskVoxelsWhoseDecisionsCanChange) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  const std::vector<double> times = {0, 1 / kFps, 2 / kFps, 2 / kFps, 3 / kFps, 4 / kFps, 5 / kFps, 6 / kFps};
  Bounds bounds;
  for (const double t : times) bounds.add(buildSceneGeometry(scene, t).bounds);
  SdfPipeline pipe(*sCtx, scene, bounds, closestAt(48, 96, 1));
  const PipelineProbe probe(pipe);
  const glm::ivec3 dims = pipe.coarseSpec().dims;
  const std::uint64_t all = pipe.coarseSpec().voxelCount();
  const auto settle = std::uint32_t(settleFramesFor(pipe.settings()));
  ASSERT_GT(settle, 1u);
  int partial = 0;
  for (std::size_t f = 0; f < times.size(); ++f) {
    SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
    const std::vector<glm::uvec2> state = probe.coarseState();
    const FrameStats st = pipe.runFrame(times[f]);
    if (f == 0) {
      EXPECT_EQ(st.maskVisitedVoxels, all);
      continue;
    }
    glm::ivec3 lo(INT32_MAX), hi(-1);
    auto add = [&](const glm::ivec3& a, const glm::ivec3& b) {
      if (glm::any(glm::greaterThan(a, b))) return;
      lo = glm::min(lo, a);
      hi = glm::max(hi, b);
    };
    if (st.movedInstances > 0) {
      const gpu::shared::ChangedBox changed = pipe.changedCoarseBox();
      add(glm::ivec3(glm::uvec3(changed.lo)), glm::ivec3(glm::uvec3(changed.hi)));
      const CoarseVoxelBox near = movedReachBox(probe.lastMovedBoxes(), pipe.coarseSpec().inFrame(pipe.frameOrigin()),
                                                pipe.settings().band + probe.lastMaskParams().reachPad);
      add(near.lo, near.hi);
    }
    std::size_t settling = 0;
    for (std::size_t i = 0; i < state.size(); ++i) {
      if (state[i].x == gpu::shared::kNotInBand || state[i].y >= settle) continue;
      const glm::ivec3 v(int(i % dims.x), int(i / dims.x % dims.y), int(i / dims.x / dims.y));
      add(v, v);
      ++settling;
    }
    hi = glm::min(hi, dims - 1);
    const gpu::shared::MaskRegion region = probe.lastMaskRegion();
    EXPECT_EQ(glm::ivec3(glm::uvec3(region.lo)), lo);
    EXPECT_EQ(glm::ivec3(glm::uvec3(region.hi)), hi);
    EXPECT_EQ(st.maskVisitedVoxels, regionVoxels(region));
    partial += st.maskVisitedVoxels < all / 2;
    std::printf("frame %zu: %zu voxels settling before; the mask visited %.1f%% of the grid\n", f + 1, settling,
                100.0 * double(st.maskVisitedVoxels) / double(all));
  }
  EXPECT_GE(partial, 3) << "once the band settled, runs over what changed visit a part of the grid";
}

// Closest mode stays the exact field behind an instance that moves off faster than a coarse diagonal a frame (a box
// crossing a floor at 1 m a frame, coarse voxels of 0.125): the voxels it leaves are refined again, and their search
// radius must come from the coarse SDF of this frame. Bounded by their last value (the box's old pose, nearer than
// anything now) plus the radius's slack, the search found nothing and stored the radius, a ghost of the old pose up to
// several voxels too near (the town's cars left such ghosts in cascade level 0). Every band voxel against the exact
// bake, every frame.
TEST_F(FramePasses, AnInstanceMovingOffFasterThanTheSearchSlackLeavesNoGhost) {
  const test::TempDir dir;
  const Scene scene = crossingBlock(dir);
  std::vector<double> times;
  for (int f = 0; f < 6; ++f) times.push_back(f / kFps);
  Bounds bounds;
  for (const double t : times) bounds.add(buildSceneGeometry(scene, t).bounds);
  PipelineSettings s = closestAt(64, 128, 0);
  s.band = 0.5; // four coarse voxels: wider than the slack, as in the town (6 fine voxels, 1.7 coarse diagonals)
  SdfPipeline pipe(*sCtx, scene, bounds, s);
  const GridSpec& ws = pipe.fineSpec();
  ASSERT_LT(std::sqrt(3.0) * pipe.coarseSpec().voxelSize, 1.0) << "the block moves farther than the slack a frame";
  ExactSdfOptions opt;
  opt.band = pipe.settings().band;
  opt.progress = false;
  for (const double t : times) {
    pipe.runFrame(t);
    const openvdb::FloatGrid::Ptr bake = exactSignedDistance(buildSceneGeometry(scene, t), ws, opt);
    const auto acc = bake->getConstAccessor();
    const std::vector<float> fine = pipe.fineField();
    const RayMask mask = pipe.rayMask();
    std::uint64_t compared = 0;
    double largest = 0.0;
    for (const std::uint32_t packed : mask.fineVoxels) {
      const glm::ivec3 v(packed & 1023u, (packed >> 10) & 1023u, (packed >> 20) & 1023u);
      float e = 0.0f;
      if (!acc.probeValue(openvdb::Coord(v.x, v.y, v.z), e)) continue;
      ++compared;
      largest = std::max(largest, std::fabs(double(fine[ws.linear(v.x, v.y, v.z)]) - e) / ws.voxelSize);
    }
    EXPECT_GT(compared, 1000u) << "t = " << t;
    EXPECT_LT(largest, 0.01) << "voxels off the exact field at t = " << t;
  }
}

// A frame whose recording throws (injected after its coarse SDF is recorded: the motion's last time, the kept
// transform, the BVH's uploaded time and the frame count moved on while nothing ran) leaves the next frame to start
// over: that frame (the failed moment again) and the ones after it equal, bit for bit, a new pipeline's from that
// moment on. Without the restart the next frame built nothing (the moment's motion counted as done) over the
// instance transforms of the frame before.
TEST_F(FramePasses, AFrameWhoseRecordingThrowsLeavesTheNextToStartOver) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  Bounds bounds;
  for (int f = 0; f < 7; ++f) bounds.add(buildSceneGeometry(scene, f / kFps).bounds);
  const PipelineSettings s = closestAt(40, 80, 1);
  SdfPipeline pipe(*sCtx, scene, bounds, s);
  pipe.runFrame(0.0);
  pipe.runFrame(1 / kFps);
  PipelineFaults(pipe).failNextRecording();
  EXPECT_THROW(pipe.submitFrame(2 / kFps), Error);
  SdfPipeline fresh(*sCtx, scene, bounds, s);
  const PipelineProbe pa(pipe), pb(fresh);
  for (int f = 2; f < 6; ++f) {
    SCOPED_TRACE(::testing::Message() << "frame at " << f << " / 30 s");
    const FrameStats a = pipe.runFrame(f / kFps), b = fresh.runFrame(f / kFps);
    EXPECT_EQ(a.skippedPasses, b.skippedPasses);
    EXPECT_EQ(a.refinedFineVoxels, b.refinedFineVoxels);
    EXPECT_EQ(a.poolBricks, b.poolBricks);
    EXPECT_EQ(differing(pipe.coarseField(), fresh.coarseField()), 0u) << "coarse voxels differ";
    EXPECT_EQ(pa.refinedVoxels(), pb.refinedVoxels());
    EXPECT_EQ(differing(pipe.fineField(), fresh.fineField()), 0u) << "fine voxels differ";
  }
}
