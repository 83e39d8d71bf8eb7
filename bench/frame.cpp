// Google Benchmark of one SdfPipeline frame (SdfPipeline::runFrame, wall time: host work, submission and the
// wait for the GPU) on the bundled scenes at the paper's size M (coarse 128 / fine 256), static scene, after a
// warm-up frame; incremental refinement (settled voxels kept) against the paper's full recompute. The per-frame CSV with host / GPU / wall split and error is `rtsdf bench --suite frame`.
#include "gpu/VulkanContext.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace {

using namespace rtsdf;

const gpu::VulkanContext& context() {
  static const auto ctx = std::make_unique<gpu::VulkanContext>(gpu::ContextOptions{});
  return *ctx;
}

/// Arguments: scene (0: default, 1: bunny), mode (0: the paper's rays, x = 1; 1: closest, x = 1), full recompute
/// (0: incremental, 1: every masked voxel every frame).
void BM_PipelineFrame(benchmark::State& state) {
  const char* scenes[] = {"default.json", "bunny.json"};
  const Scene scene = loadScene(std::string(RTSDF_DATA_DIR) + "/scenes/" + scenes[state.range(0)]);
  PipelineSettings s;
  s.coarseRes = 128;
  s.fineRes = 256;
  s.rays = 1;
  s.band = 0.1; // scene units, as the recorded figures
  s.mode = state.range(1) == 1 ? RefineMode::Closest : RefineMode::Rays;
  s.fullRecompute = state.range(2) == 1;
  SdfPipeline pipe(context(), scene, buildSceneGeometry(scene, 0.0).bounds, s);
  FrameStats last = pipe.runFrame(0.0);
  for (auto _ : state) last = pipe.runFrame(0.0);
  double gpu = 0.0;
  for (const auto& [name, ms] : last.passMs) gpu += ms;
  state.counters["gpu_ms"] = gpu;
  state.counters["mask_voxels"] = double(last.maskFineVoxels);
  state.counters["refined_voxels"] = double(last.refinedFineVoxels);
  state.SetLabel(std::string(scenes[state.range(0)]) + (state.range(1) ? " closest x=1" : " rays x=1") +
                 (state.range(2) ? " full recompute" : " incremental"));
}
BENCHMARK(BM_PipelineFrame)
    ->ArgsProduct({{0, 1}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

} // namespace

BENCHMARK_MAIN();
