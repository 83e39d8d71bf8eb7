// Cascade levels above 0 refined only near the camera's view (CascadeSet::setView, SdfPipeline::setViewReach): the
// band out of the view's reach keeps the coarse SDF, the rest is what a level without the limit holds, a camera that
// turns gives the levels a level built for its new view would have, the mask's decisions are its CPU copy's, and the
// cone test agrees with the distance to the cone in closed form.
#include "CascadeTestLevels.h"
#include "GpuFixture.h"
#include "TestUtil.h"
#include "jobs/Animate.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/cascade/CascadeSet.h"
#include "sdf/mask/MaskCpu.h"
#include "sdf/pipeline/PipelineProbe.h"
#include "sdf/refine/RefineCpu.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace rtsdf;

namespace {

struct CascadeViewTag : test::NoSuiteObjects {};
using CascadeViewGpu = test::VulkanSuite<CascadeViewTag>;

/// test::threeLevels at coarse 24 / fine 48, the view's margin one coarse voxel of each level.
PipelineSettings viewLevels() {
  PipelineSettings s = test::threeLevels();
  s.coarseRes = 24;
  s.fineRes = 48;
  s.cascadeViewMargin = 1.0;
  return s;
}

constexpr double kAspect = 16.0 / 9.0;

/// The default room's camera looking from @a position towards @a target with a narrow view.
Camera eye(const glm::dvec3& position, const glm::dvec3& target) {
  Camera c;
  c.position = position;
  c.target = target;
  c.verticalFov = 0.5;
  return c;
}

/// The distance from @a p to the cone of @a r (apex, axis, half-angle; its margin not added), 0 inside: in closed
/// form, apart from the mask's test.
double distanceToCone(const ViewReach& r, const glm::dvec3& p) {
  const glm::dvec3 d = p - r.apex;
  const double t = glm::dot(d, r.axis);
  const double across = glm::length(d - t * r.axis);
  if (t * std::cos(r.halfAngle) + across * std::sin(r.halfAngle) < 0.0) return glm::length(d); // nearest: the apex
  return std::max(0.0, across * std::cos(r.halfAngle) - t * std::sin(r.halfAngle));
}

using test::largestDifference;

} // namespace

// Against a set without the limit on the same grids: level 0 is the same field; above it, every fine voxel the mask
// left out of view holds the coarse SDF upsampled (RefineCpu's upsampleCoarse), every other voxel the value the
// unlimited level holds (the band in view refined exactly alike), and fewer voxels were refined. The cone test against
// the cone's distance in closed form: a voxel left out lies beyond the margin of the cone; one refined lies within
// its cell's reach of it (behind the camera the test errs on the side of refining: within that reach over the smaller
// of the half-angle's sine and cosine).
TEST_F(CascadeViewGpu, LevelsAboveZeroRefineNearTheViewAndKeepTheCoarseSdfElsewhere) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  const PipelineSettings s = viewLevels();
  const Camera camera = eye({-0.3, 0.45, 0.1}, {0.4, 0.2, -0.3});
  const CascadeLayout layout =
      CascadeLayout::around(camera.position, cascadeShapeFor(buildSceneGeometry(scene).bounds, s));
  CascadeSet limited(*sCtx, scene, layout, s);
  limited.setView(camera, kAspect);
  const std::vector<FrameStats> stats = limited.runFrame(0.0);
  CascadeSet whole(*sCtx, scene, layout, s);
  const std::vector<FrameStats> wholeStats = whole.runFrame(0.0);
  for (int i = 0; i < limited.levels(); ++i) {
    SCOPED_TRACE("level " + std::to_string(i));
    const SdfPipeline& level = limited.level(i);
    const std::vector<float> fine = level.fineField(), unlimited = whole.level(i).fineField();
    const std::vector<std::uint32_t> out = level.outOfViewVoxels();
    if (i == 0) {
      EXPECT_TRUE(out.empty()) << "level 0 refines its whole band";
      EXPECT_EQ(largestDifference(fine, unlimited), 0.0);
      continue;
    }
    const GridSpec& fs = level.fineSpec();
    ASSERT_GT(out.size(), 100u);
    EXPECT_LT(stats[std::size_t(i)].refinedFineVoxels, wholeStats[std::size_t(i)].refinedFineVoxels);
    const std::vector<float> coarse = level.coarseField();
    const GridSpec cs = level.coarseSpec().inFrame(level.frameOrigin()), fsFrame = fs.inFrame(level.frameOrigin());
    std::vector<char> isOut(fine.size(), 0);
    for (std::uint32_t packed : out) {
      const glm::ivec3 v = test::unpackVoxel(packed);
      isOut[fs.linear(v.x, v.y, v.z)] = 1;
    }
    std::uint64_t outDiffer = 0, inDiffer = 0;
    for (int z = 0; z < fs.dims.z; ++z)
      for (int y = 0; y < fs.dims.y; ++y)
        for (int x = 0; x < fs.dims.x; ++x) {
          const std::size_t k = fs.linear(x, y, z);
          if (isOut[k]) outDiffer += fine[k] != upsampleCoarse(coarse, cs, fsFrame, {x, y, z});
          else inDiffer += fine[k] != unlimited[k];
        }
    EXPECT_EQ(outDiffer, 0u) << "out of view: the coarse SDF upsampled";
    EXPECT_EQ(inDiffer, 0u) << "elsewhere: the level without the limit";
    // The error against the exact field counts the voxels in reach only: a part of the whole level's, no worse.
    const FieldError e = fieldErrorAgainstExact(limited.levelScene(i), level, 0.0);
    const FieldError eWhole = fieldErrorAgainstExact(whole.levelScene(i), whole.level(i), 0.0);
    EXPECT_GT(e.voxels, 0u);
    EXPECT_LT(e.voxels, eWhole.voxels);
    EXPECT_LE(e.maxAbs, eWhole.maxAbs);
    EXPECT_LE(e.signMismatches, eWhole.signMismatches);
    // The cone, in closed form.
    const double h = level.coarseSpec().voxelSize, margin = s.cascadeViewMargin * h;
    const ViewReach reach = viewReachOf(camera, kAspect, margin);
    const double cellReach = std::sqrt(3.0) * h + margin;
    const double slack = 1e-4 * h; // the mask tests in floats
    double nearestOut = HUGE_VAL, farthestIn = 0.0;
    for (std::uint32_t packed : out) {
      const glm::ivec3 v = test::unpackVoxel(packed);
      nearestOut = std::min(nearestOut, distanceToCone(reach, fs.indexToWorld(glm::dvec3(v))));
    }
    for (std::uint32_t packed : level.rayMask().fineVoxels) {
      const glm::ivec3 v = test::unpackVoxel(packed);
      if (!isOut[fs.linear(v.x, v.y, v.z)])
        farthestIn = std::max(farthestIn, distanceToCone(reach, fs.indexToWorld(glm::dvec3(v))));
    }
    EXPECT_GT(nearestOut, margin - slack);
    EXPECT_LT(farthestIn, cellReach / std::min(std::cos(reach.halfAngle), std::sin(reach.halfAngle)) + slack);
    std::printf("level %d: %zu of %zu band voxels out of view, refined %llu of %llu; out of view at least %.4f from "
                "the cone (margin %.4f), refined at most %.4f\n",
                i, out.size(), level.rayMask().fineVoxels.size(),
                (unsigned long long)stats[std::size_t(i)].refinedFineVoxels,
                (unsigned long long)wholeStats[std::size_t(i)].refinedFineVoxels, nearestOut, margin, farthestIn);
  }
}

// A camera that holds still while the teapot orbits, then turns: after each frame every level equals a level built
// fresh for that view at that time, kept dense and kept sparse (the field resolved from the bricks). The frames that
// hold still write the band out of view again only where the coarse SDF changed: the held view leaves slotted bricks'
// voxels out of reach where the teapot changes level 2's coarse SDF (found by trying views around the camera; with
// nothing written again there, 89 to 99 voxels differ). The turns refine fewer voxels than the fresh builds.
TEST_F(CascadeViewGpu, ATurningCameraGivesTheLevelsAFreshBuildForItsViewWouldHave) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  const glm::dvec3 position(-0.3, 0.45, 0.1);
  // Held for frames 0-3; then turns of about 16 degrees, against a view cone of about 28 degrees around its axis.
  const glm::dvec3 held(0.08, 0.15, 1.02);
  const glm::dvec3 turns[] = {{0.4, 0.2, -0.3}, {0.4, 0.2, -0.1}, {0.4, 0.2, 0.1}, {0.35, 0.2, 0.3}};
  for (const FineStorage storage : {FineStorage::Dense, FineStorage::Sparse}) {
    SCOPED_TRACE(toString(storage));
    PipelineSettings s = viewLevels();
    s.fineStorage = storage;
    const CascadeLayout layout =
        CascadeLayout::around(position, cascadeShapeFor(buildSceneGeometry(scene).bounds, s));
    CascadeSet set(*sCtx, scene, layout, s);
    std::uint64_t turned = 0, fresh = 0;
    for (int f = 0; f < 8; ++f) {
      const Camera camera = eye(position, f < 4 ? held : turns[f - 4]);
      const double t = f / 30.0;
      set.setView(camera, kAspect);
      const std::vector<FrameStats> stats = set.runFrame(t);
      CascadeSet built(*sCtx, scene, layout, s);
      built.setView(camera, kAspect);
      const std::vector<FrameStats> builtStats = built.runFrame(t);
      for (int i = 0; i < set.levels(); ++i) {
        SCOPED_TRACE("frame " + std::to_string(f) + ", level " + std::to_string(i));
        EXPECT_EQ(largestDifference(set.level(i).fineField(), built.level(i).fineField()), 0.0);
        EXPECT_TRUE(set.level(i).outOfViewVoxels() == built.level(i).outOfViewVoxels());
        if (f > 4 && i > 0) {
          turned += stats[std::size_t(i)].refinedFineVoxels;
          fresh += builtStats[std::size_t(i)].refinedFineVoxels;
        }
      }
    }
    EXPECT_GT(turned, 0u) << "the voxels that came into view";
    EXPECT_LT(double(turned), 0.7 * double(fresh));
    std::printf("%s: turning, levels 1-2 refined %.3f of the voxels fresh builds did\n", toString(storage),
                double(turned) / double(fresh));
  }
}

// MaskCompactPass's view decisions against maskDecisionsCpu, frame by frame on level 2 while the camera turns and then
// holds still as the teapot orbits: the same voxels refined (fresh flags included: a voxel that comes into view starts
// afresh), the same voxels out of view written again (all after a turn, only near the coarse SDF's change after), the
// same state after.
TEST_F(CascadeViewGpu, TheMasksViewDecisionsEqualTheCpuCopy) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  const PipelineSettings s = viewLevels();
  const glm::dvec3 position(-0.3, 0.45, 0.1);
  const CascadeLayout layout = CascadeLayout::around(position, cascadeShapeFor(buildSceneGeometry(scene).bounds, s));
  CascadeSet set(*sCtx, scene, layout, s);
  // Two turns, then the view the test above holds, held while the teapot orbits on.
  const glm::dvec3 targets[] = {{0.4, 0.2, -0.3}, {0.4, 0.2, -0.1}, {0.08, 0.15, 1.02}};
  bool sawFreshInView = false, sawSomeRewritten = false;
  for (int f = 0; f < 6; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    set.setView(eye(position, targets[std::min(f, 2)]), kAspect);
    const SdfPipeline& level = set.level(2); // it holds the teapot's orbit
    const PipelineProbe probe(level);
    const std::vector<glm::uvec2> before = f == 0 ? std::vector<glm::uvec2>() : probe.coarseState();
    // After the turns, a quarter of a second a frame: the teapot's seeds in level 2's coarse voxels change every few
    // tenths (decided by their world voxel alone, as a full build's: CoarseSdfSettings::seedLatticeCell).
    set.runFrame(f <= 2 ? f / 30.0 : 2 / 30.0 + (f - 2) * 0.25);
    if (f == 0) continue; // the first frame's state starts from the pool's reset
    const MaskDecisions cpu = maskDecisionsCpu(level.coarseField(), level.coarseSpec(), level.fineSpec(), before,
                                               probe.lastMaskParams(), probe.lastMovedBoxes(),
                                               level.changedCoarseBox());
    const std::vector<std::uint32_t> refined = probe.refinedVoxels();
    EXPECT_TRUE(refined == cpu.refined) << refined.size() << " refined on the GPU, " << cpu.refined.size()
                                        << " on the CPU";
    const std::vector<std::uint32_t> rewritten = probe.rewrittenVoxels();
    EXPECT_TRUE(rewritten == cpu.rewritten) << rewritten.size() << " written again on the GPU, "
                                            << cpu.rewritten.size() << " on the CPU";
    EXPECT_TRUE(probe.coarseState() == cpu.state);
    const std::size_t outOfView = level.outOfViewVoxels().size();
    EXPECT_GT(outOfView, 0u);
    if (f <= 2) EXPECT_EQ(cpu.rewritten.size(), outOfView) << "after a turn, all of them";
    else sawSomeRewritten |= !cpu.rewritten.empty() && cpu.rewritten.size() < outOfView;
    for (std::uint32_t packed : refined) sawFreshInView |= (packed & gpu::shared::kMaskFineFresh) != 0u;
  }
  EXPECT_TRUE(sawFreshInView) << "the turns brought voxels into view";
  EXPECT_TRUE(sawSomeRewritten) << "the teapot changed the coarse SDF in part of the band out of view";
}
