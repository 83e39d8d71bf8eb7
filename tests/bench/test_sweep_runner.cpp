// The sweep runner on real scenes through the GPU pipeline (lavapipe in CI), validation on.
#include "TestUtil.h"
#include "bench/SweepPlots.h"
#include "bench/SweepRunner.h"
#include "image/ImageIO.h"
#include "scene/SceneLoader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace rtsdf;
using namespace rtsdf::bench;

namespace {

SweepPoint xs(SweepGroup g, RefineMode mode, int rays, int frames = 2) {
  SweepPoint p;
  p.group = g;
  p.size = "XS";
  p.pipeline.coarseRes = 24;
  p.pipeline.fineRes = 48;
  p.pipeline.mode = mode;
  p.pipeline.rays = rays;
  p.frames = frames;
  return p;
}

SweepRunOptions options() {
  SweepRunOptions o;
  o.shadowWidth = 64;
  o.shadowHeight = 36;
  o.truthSamples = 64;
  o.animationFrames = 3;
  return o;
}

} // namespace

TEST(SweepRunner, MeasuresPointsAnchorsAndStorageOnTheBunny) {
  const Scene scene = loadScene(test::dataPath("scenes/bunny.json"));
  SweepRunner runner(scene, options());
  EXPECT_FALSE(runner.animated());
  EXPECT_TRUE(runner.measuresShadows());

  const auto closest = runner.run(xs(SweepGroup::Sizes, RefineMode::Closest, 0));
  ASSERT_EQ(closest.size(), 1u);
  const SweepRecord& c = closest[0];
  ASSERT_TRUE(c.ok()) << c.note;
  // Closest-point refinement is exact in the band; the band is all the error band needs.
  EXPECT_GT(c.errorVoxels, 1000u);
  EXPECT_LT(c.meanAbs, 0.05);
  EXPECT_GT(c.maskVoxels, 1000u);
  EXPECT_GT(c.frameMs, 0.0);
  EXPECT_GT(c.refineMs, 0.0);
  EXPECT_GT(c.jumpFloodMs, 0.0);
  EXPECT_GT(c.peakMiB, 10.0);
  EXPECT_TRUE(std::isfinite(c.shadowRmse) && c.shadowRmse < 0.5);
  EXPECT_TRUE(std::isfinite(c.shadowFlip));

  // More rays, less error (x = 0 leaves the upsampled coarse field).
  const SweepRecord r0 = runner.run(xs(SweepGroup::Sizes, RefineMode::Rays, 0))[0];
  const SweepRecord r4 = runner.run(xs(SweepGroup::Sizes, RefineMode::Rays, 4))[0];
  ASSERT_TRUE(r0.ok() && r4.ok());
  EXPECT_LT(r4.meanAbs, 0.8 * r0.meanAbs);
  EXPECT_GT(r4.meanAbs, c.meanAbs);

  SweepPoint exact = xs(SweepGroup::Anchor, RefineMode::Closest, 0, 1);
  exact.anchor = AnchorKind::Exact;
  const SweepRecord e = runner.run(exact)[0];
  ASSERT_TRUE(e.ok()) << e.note;
  EXPECT_EQ(e.meanAbs, 0.0);
  EXPECT_EQ(e.voxelSize, c.voxelSize) << "anchors use the pipeline's fine voxels";
  SweepPoint vdb = exact;
  vdb.anchor = AnchorKind::OpenVdb;
  const SweepRecord v = runner.run(vdb)[0];
  ASSERT_TRUE(v.ok()) << v.note;
  EXPECT_GT(v.meanAbs, 0.0);
  EXPECT_LT(v.meanAbs, 0.5);

  SweepPoint storage = xs(SweepGroup::Storage, RefineMode::Closest, 0, 1);
  storage.storageBandVoxels = 3;
  const SweepRecord s = runner.run(storage)[0];
  ASSERT_TRUE(s.ok()) << s.note;
  EXPECT_GT(s.vdbBytes, 0u);
  EXPECT_LT(s.vdbBytes, s.denseBytes);
  int gx = 0, gy = 0, gz = 0;
  ASSERT_EQ(std::sscanf(s.grid.c_str(), "%dx%dx%d", &gx, &gy, &gz), 3) << s.grid;
  EXPECT_EQ(s.denseBytes, 4u * std::uint64_t(gx) * std::uint64_t(gy) * std::uint64_t(gz));

  // A point beyond the device is a record that says why, not an abort.
  SweepPoint huge = xs(SweepGroup::Sizes, RefineMode::Closest, 0);
  huge.pipeline.coarseRes = 1024;
  huge.pipeline.fineRes = 1024;
  if (runner.device().maxStorageBufferRange < 1024ull * 1024 * 1024 * 4) {
    const SweepRecord h = runner.run(huge)[0];
    EXPECT_FALSE(h.ok());
    EXPECT_FALSE(h.note.empty());
  }
  EXPECT_EQ(runner.context().validationErrors(), 0u) << runner.context().lastValidationMessage();

  // The plots of these records: PNGs that decode.
  test::TempDir dir;
  const auto pngs = writeSweepPlots(dir.path(), {c, r0, r4, e, v}, "bunny");
  ASSERT_GE(pngs.size(), 2u);
  for (const auto& p : pngs) {
    EXPECT_GT(readPng(dir.path() / p).width, 500) << p;
  }
}

TEST(SweepRunner, DynamicPointsGiveOneRecordPerFrameAndStopWhenAsked) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  SweepRunOptions o = options();
  int polls = 0;
  bool stop = false;
  o.stopRequested = [&] { ++polls; return stop; };
  SweepRunner runner(scene, o);
  ASSERT_TRUE(runner.animated());
  const auto frames = runner.run(xs(SweepGroup::Dynamic, RefineMode::Closest, 0, 3));
  ASSERT_EQ(frames.size(), 3u);
  for (int f = 0; f < 3; ++f) {
    EXPECT_TRUE(frames[f].ok()) << frames[f].note;
    EXPECT_EQ(frames[f].frame, f);
    EXPECT_DOUBLE_EQ(frames[f].time, f / o.fps);
    // Exact distances every frame, against the exact field of that frame: the moving teapot leaves no ghost.
    EXPECT_LT(frames[f].meanAbs, 0.05) << "frame " << f;
  }
  EXPECT_GE(polls, 3);
  stop = true;
  EXPECT_THROW(runner.run(xs(SweepGroup::Sizes, RefineMode::Rays, 1)), SweepInterrupted);
  EXPECT_EQ(runner.context().validationErrors(), 0u) << runner.context().lastValidationMessage();
}
