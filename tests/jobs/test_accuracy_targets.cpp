// Accuracy targets once met, held at their measured values plus a small margin (docs/results.md records each
// measurement and its command): a change that loses one fails here, not in the next benchmark run.
#include "TestUtil.h"
#include "jobs/Animate.h"
#include "jobs/RenderJob.h"
#include "metrics/FieldError.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

using namespace rtsdf;

// The default scene's static frame at 640x360 against the ray-traced truth (256 samples), as
// `rtsdf render data/scenes/default.json --frames 1 --no-taa --no-jitter --compare` measures it. The targets were
// penumbra RMSE <= 0.10 and umbra mean |diff| <= 0.01; measured 0.0946 and 0.0058 (1009 and 2157 pixels, lavapipe)
// when the contact rays met them, and the same today. The margin is 0.003 and 0.0007. Jitter off: a single
// jittered frame is noisier (0.1016) by design, TAA integrates the jitter over frames.
TEST(AccuracyTargets, DefaultSceneStaticFramePenumbraAndUmbra) {
  RenderJobOptions o;
  o.scene = test::dataPath("scenes/default.json");
  o.frames = 1;
  o.compare = true;
  o.render.sdf.jitter = false;
  o.render.taa.enabled = false;
  // The settings the targets were met with (render's former defaults): fine 256 over coarse 64, d = 0.1.
  o.render.pipeline.coarseRes = 64;
  o.render.pipeline.fineRes = 256;
  o.render.pipeline.band = 0.1;
  o.render.pipeline.mode = RefineMode::Closest;
  o.render.pipeline.rays = 0;
  ASSERT_EQ(o.render.width, 640);
  ASSERT_EQ(o.render.height, 360);
  const RenderJobResult r = renderScene(o);
  ASSERT_TRUE(r.compared);
  std::printf("default scene, static frame at 640x360: penumbra RMSE %.4f (%zu px), umbra mean |diff| %.4f (%zu px)\n",
              r.error.penumbraRmse, r.error.penumbraPixels, r.error.umbraMeanAbs, r.error.umbraPixels);
  EXPECT_GT(r.error.penumbraPixels, 900u);
  EXPECT_GT(r.error.umbraPixels, 2000u);
  EXPECT_LE(r.error.penumbraRmse, 0.0976);
  EXPECT_LE(r.error.umbraMeanAbs, 0.0065);
}

// The incremental frame (closest mode, x = 1) against the full recompute on the animated default scene: the
// target was a mean error within 0.05 voxels of the recompute's (met at M: 0.00003 voxels above at worst). At S
// (coarse 64, fine 128), 6 frames, measured on lavapipe: the same errors to the printed digit in every frame, mean
// 0.000187-0.000305 voxels, wrong signs 0.0043%-0.0226%. Held: equal within 1e-4 voxels, mean <= 0.0004 voxels,
// wrong signs <= 0.03%.
TEST(AccuracyTargets, IncrementalFramesMatchTheFullRecomputeAtS) {
  std::vector<FieldError> errors[2];
  for (const bool full : {false, true}) {
    AnimateOptions a;
    a.scene = test::dataPath("scenes/default.json");
    a.frames = 6;
    a.pipeline = PipelineSettings{};
    a.pipeline.coarseRes = 64;
    a.pipeline.fineRes = 128;
    a.pipeline.band = 0.1; // the band (scene units) the target was measured with
    a.pipeline.mode = RefineMode::Closest;
    a.pipeline.rays = 1;
    a.pipeline.fullRecompute = full;
    animate(a, {}, [&](const AnimateFrame& f) { errors[full].push_back(f.error); });
  }
  ASSERT_EQ(errors[0].size(), 6u);
  ASSERT_EQ(errors[1].size(), 6u);
  for (std::size_t f = 0; f < errors[0].size(); ++f) {
    SCOPED_TRACE(f);
    const FieldError& inc = errors[0][f];
    const FieldError& full = errors[1][f];
    std::printf("frame %zu: incremental mean %.6f voxels, wrong signs %.4f%%; full %.6f, %.4f%%\n", f + 1, inc.meanAbs,
                100.0 * inc.signErrorRate(), full.meanAbs, 100.0 * full.signErrorRate());
    EXPECT_GT(inc.voxels, 1000u);
    EXPECT_NEAR(inc.meanAbs, full.meanAbs, 1e-4);
    EXPECT_LE(inc.meanAbs, 0.0004);
    EXPECT_LE(inc.signErrorRate(), 3e-4);
  }
}
