// `rtsdf bench --suite render`: per-pass times of each shadow technique and its error against the truth.
#include "suites/SuiteTables.h"

#include "image/ImageIO.h"
#include "jobs/JobSupport.h"
#include "jobs/RenderJob.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Progress.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <thread>
#include <tuple>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

/// Per-pass GPU times (median over frames after two warm-up frames) of one technique, as table rows; the
/// last frame is kept for its error.
struct TechniqueTiming {
  std::string rows;
  double totalMs = 0.0;
  RenderedFrame last;
};

/// @a fps > 0: the frames are the scene's animation at that rate from time 0 (else every frame at time 0).
TechniqueTiming timeTechnique(const gpu::VulkanContext& ctx, const Scene& scene, const RenderSettings& rs,
                              const std::string& name, int frames, double warmUpSeconds, double fps = 0.0) {
  const auto timeOf = [&](int f) { return fps > 0.0 ? f / fps : 0.0; };
  Bounds bounds;
  for (int f = 0; f < frames + 2; ++f) bounds.add(buildSceneGeometry(scene, timeOf(f)).bounds);
  if (warmUpSeconds > 0.0) { // the GPU's clocks, on a renderer of its own: the measured frames' TAA history stays
    Renderer warm(ctx, scene, bounds, rs);
    warmUpGpu(warmUpSeconds, [&] { warm.renderFrame(0.0, false); });
  }
  Renderer r(ctx, scene, bounds, rs);
  std::map<std::string, std::vector<double>> ms;
  std::vector<std::string> order;
  std::vector<double> totals;
  TechniqueTiming t;
  Progress progress(fmt::format("render {} {}x{}", name, rs.width, rs.height), std::uint64_t(frames + 2));
  for (int f = 0; f < frames + 2; ++f) {
    t.last = r.renderFrame(timeOf(f), f + 1 == frames + 2);
    progress.add();
    if (f < 2) continue;
    std::map<std::string, double> sum;
    for (const auto& [n, v] : t.last.passMs) {
      if (!sum.count(n) && !ms.count(n)) order.push_back(n);
      sum[n] += v;
    }
    for (const auto& [n, v] : sum) ms[n].push_back(v);
    totals.push_back(passSum(t.last.passMs));
  }
  progress.finish();
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
  };
  for (const auto& n : order) t.rows += fmt::format("| {} | {} | {:.2f} |\n", name, n, median(ms[n]));
  t.totalMs = median(totals);
  t.rows += fmt::format("| {} | **frame total** | **{:.2f}** ({:.1f} fps) |\n", name, t.totalMs, 1000.0 / t.totalMs);
  return t;
}

using ErrorRows = std::vector<std::tuple<std::string, ShadowImageError, double>>;

/// The ray tracer at fewer samples than the truth: its time and error against the truth.
void timeRayTracer(const Scene& scene, RenderSettings rs, const RenderedFrame& truth, ErrorRows& errors) {
  for (int samples : {1, 4, 16, 64}) {
    rs.rayTraced.samples = samples;
    rs.rayTraced.seed = 99; // independent of the truth's samples
    const auto t0 = std::chrono::steady_clock::now();
    const RenderedFrame f = renderRayTraced(scene, 0.0, rs);
    const double ms = 1e3 * secondsSince(t0);
    errors.emplace_back(fmt::format("raytraced, {} spp (CPU, {} threads)", samples, std::thread::hardware_concurrency()),
                        compareWithTruth(scene, f, truth), ms);
  }
}

/// One scene at one image size: the techniques' pass tables, then their errors beside the ray tracer's.
std::string renderSize(const gpu::VulkanContext& ctx, const BenchOptions& s, const std::string& path,
                       const Scene& scene, glm::ivec2 size) {
  const int truthSamples = 1024, frames = 4;
  RenderSettings rs = RenderJobOptions::defaultRenderSettings();
  rs.width = size.x;
  rs.height = size.y;
  rs.rayTraced.samples = truthSamples;
  const auto tt0 = std::chrono::steady_clock::now();
  const RenderedFrame truth = renderRayTraced(scene, 0.0, rs);
  const double truthS = secondsSince(tt0);
  const std::string stem = fs::path(path).stem().string();
  const bool pictures = !s.output.empty() && size.x == 640;
  std::string md = fmt::format("### {} at {}x{}\n\n", fs::path(path).filename().string(), size.x, size.y);
  md += "| technique | pass | GPU ms (median) |\n|---|---|---|\n";
  ErrorRows errors;
  // SDF shadows every way of sampling the field (hardware-filtered 3D texture, shader-filtered dense buffer, the
  // sparse brick pool with no dense copy).
  for (const auto& [t, sampling] : {std::pair{ShadowTechnique::Sdf, SdfSampling::Texture},
                                    std::pair{ShadowTechnique::Sdf, SdfSampling::Buffer},
                                    std::pair{ShadowTechnique::Sdf, SdfSampling::Bricks},
                                    std::pair{ShadowTechnique::ShadowMap, SdfSampling::Texture}}) {
    rs.technique = t;
    rs.sdf.sampling = sampling;
    const std::string name =
        t == ShadowTechnique::Sdf ? fmt::format("sdf ({})", toString(sampling)) : std::string(toString(t));
    const TechniqueTiming timing = timeTechnique(ctx, scene, rs, name, frames, s.warmUpSeconds);
    md += timing.rows;
    errors.emplace_back(name, compareWithTruth(scene, timing.last, truth), timing.totalMs);
    if (pictures && sampling == SdfSampling::Texture)
      writePng(s.output.parent_path() / fmt::format("{}_{}.png", stem, toString(t)),
               displayImage(composeImage(scene, timing.last)));
  }
  // The scene's animation at 30 fps, SDF shadows from the texture: on a GPU each frame updates it where the pipeline
  // wrote the fine SDF (VolumeUpdatePass; a CPU device fills it whole); with every pass over the whole grid
  // (--full-rebuild) it is filled whole. Timings only (their pictures would be of other moments than the truth's).
  for (const bool whole : {false, true}) {
    RenderSettings moving = rs;
    moving.technique = ShadowTechnique::Sdf;
    moving.sdf.sampling = SdfSampling::Texture;
    moving.pipeline.fullRebuild = whole;
    const std::string name = whole ? "sdf (texture), moving, every pass (--full-rebuild)" : "sdf (texture), moving";
    md += timeTechnique(ctx, scene, moving, name, frames, s.warmUpSeconds, 30.0).rows;
  }
  if (pictures)
    writePng(s.output.parent_path() / fmt::format("{}_raytraced.png", stem), displayImage(composeImage(scene, truth)));
  timeRayTracer(scene, rs, truth, errors);
  md += fmt::format("\n| technique | frame ms | mean abs vis error | penumbra RMSE ({} px) | umbra mean abs diff ({} px) "
                    "| FLIP |\n|---|---|---|---|---|---|\n",
                    std::get<1>(errors[0]).penumbraPixels, std::get<1>(errors[0]).umbraPixels);
  for (const auto& [name, e, ms] : errors)
    md += fmt::format("| {} | {:.1f} | {:.4f} | {:.4f} | {:.4f} | {:.4f} |\n", name, ms, e.visibilityMeanAbs,
                      e.penumbraRmse, e.umbraMeanAbs, e.flip);
  md += fmt::format("| raytraced truth, {} spp (CPU) | {:.1f} | 0 | 0 | 0 | 0 |\n\n", truthSamples, 1e3 * truthS);
  return md;
}

/// The render suite's tables on @a ctx.
std::string renderTables(const gpu::VulkanContext& ctx, const BenchOptions& s, const JobControl& control) {
  std::string md = fmt::format(
      "GPU: {} ({}). GPU pass times: median over {} frames after {} warm-up frames and {} s of frames on a renderer "
      "of its own (GPU timestamps). Error against "
      "the ray-traced truth ({} samples per pixel) of the same frame: visibility mean |diff| over lit surfaces, "
      "RMSE in the truth's penumbra (0.02 < V < 0.98), mean |diff| in its umbra (V < 0.02), mean LDR-FLIP of the "
      "pictures.\n\n",
      ctx.info().name, ctx.info().driver, 4, 2, s.warmUpSeconds, 1024);
  JobPoll poll(&control, "render suite", 2 * s.scenes.size()); // two sizes per scene
  for (const std::string& path : s.scenes) {
    const Scene scene = loadScene(path);
    if (!scene.hasCamera || scene.lights.empty()) {
      poll.done(2);
      continue;
    }
    for (const glm::ivec2 size : {glm::ivec2(640, 360), glm::ivec2(1280, 720)}) {
      control.checkStop();
      md += renderSize(ctx, s, path, scene, size);
      poll.done();
    }
  }
  return md;
}

} // namespace

std::string renderSuite(const BenchOptions& s, const JobControl& control) {
  return runOnDevice(deviceContextOptions(s.device),
                     [&](const gpu::VulkanContext& ctx) { return renderTables(ctx, s, control); });
}

} // namespace rtsdf::bench
