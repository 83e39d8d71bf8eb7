// Embedding rtsdf: load a scene, run a few animated frames of the SDF pipeline on the GPU, then write the last
// frame's fine SDF (its narrow band) as a .vdb and a picture of the scene's soft shadows sphere-traced through it.
//
//   embed SCENE OUT_PREFIX [FRAMES]   writes OUT_PREFIX.vdb and OUT_PREFIX.png
#include "gpu/VulkanContext.h"
#include "grid/VdbIO.h"
#include "image/ImageIO.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"
#include "util/Error.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

constexpr double kFps = 30.0;

/// The SDF settings of both the frames and the picture: the paper's size S, exact refinement.
rtsdf::PipelineSettings pipelineSettings() {
  rtsdf::PipelineSettings s;
  s.coarseRes = 64;
  s.fineRes = 128;
  s.mode = rtsdf::RefineMode::Closest;
  s.rays = 0;
  return s;
}

int run(const std::string& scenePath, const std::string& outPrefix, int frames) {
  const rtsdf::Scene scene = rtsdf::loadScene(scenePath);
  // The grids stay fixed over the animation: they cover the scene at every frame's moment.
  rtsdf::Bounds bounds;
  for (int f = 0; f < frames; ++f) bounds.add(rtsdf::buildSceneGeometry(scene, f / kFps).bounds);
  rtsdf::gpu::VulkanContext ctx; // the best Vulkan device
  std::printf("device: %s\n", ctx.info().name.c_str());

  rtsdf::SdfPipeline pipeline(ctx, scene, bounds, pipelineSettings());
  for (int f = 0; f < frames; ++f) {
    pipeline.submitFrame(f / kFps); // records and submits; the host is free until finishFrame()
    const rtsdf::FrameStats stats = pipeline.finishFrame();
    std::printf("frame %d: %llu band voxels, %llu refined, host %.2f ms, wall %.1f ms\n", f + 1,
                static_cast<unsigned long long>(stats.maskFineVoxels),
                static_cast<unsigned long long>(stats.refinedFineVoxels), stats.hostMs, stats.wallMs);
  }

  // The fine SDF's narrow band as an OpenVDB level set (what Blender and OpenVDB's tools read), stamped like the
  // command line's bakes, so `rtsdf compare OUT.vdb --against exact` finds its scene, band and moment.
  const double band = pipeline.settings().band, time = (frames - 1) / kFps;
  const openvdb::FloatGrid::Ptr grid = pipeline.levelSet(static_cast<float>(band));
  rtsdf::stampLevelSet(*grid, pipeline.fineSpec(),
                       {{"scene", rtsdf::recordedScenePath(scenePath)}, {"band", band}, {"time", time}});
  rtsdf::writeVdb(outPrefix + ".vdb", {grid});
  std::printf("%s.vdb: %llu active voxels\n", outPrefix.c_str(),
              static_cast<unsigned long long>(grid->activeVoxelCount()));

  // The scene's camera view with SDF soft shadows at the last frame's moment (the renderer runs its own
  // pipeline with the same settings; its temporal filter needs a few frames).
  rtsdf::RenderSettings render;
  render.width = 320;
  render.height = 180;
  render.pipeline = pipelineSettings();
  rtsdf::Renderer renderer(ctx, scene, bounds, render);
  rtsdf::RenderedFrame frame;
  for (int f = 0; f < frames; ++f) frame = renderer.renderFrame(f / kFps);
  rtsdf::writePng(outPrefix + ".png", rtsdf::composeImage(scene, frame));
  std::printf("%s.png: %dx%d\n", outPrefix.c_str(), render.width, render.height);
  // With RTSDF_VALIDATION=1 (as the tests run it) the Vulkan validation layer counts errors: any is a failure.
  if (ctx.validationErrors()) {
    std::fprintf(stderr, "%u Vulkan validation errors\n", ctx.validationErrors());
    return 1;
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: %s SCENE OUT_PREFIX [FRAMES]\n", argv[0]);
    return 2;
  }
  const int frames = argc == 4 ? std::atoi(argv[3]) : 4;
  if (frames < 1 || frames > 1000) {
    std::fprintf(stderr, "%s: FRAMES must be in [1, 1000]\n", argv[0]);
    return 2;
  }
  try {
    return run(argv[1], argv[2], frames);
  } catch (const rtsdf::Error& e) { // bad scenes, settings, no Vulkan device, failed writes
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 1;
  }
}
