// rtsdf render: soft shadows of a scene's camera view as a linear EXR and an sRGB PNG.
#include "Commands.h"

#include "gpu/VulkanContext.h"
#include "image/ImageIO.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"
#include "util/Progress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <map>

namespace rtsdf::app {
namespace fs = std::filesystem;

namespace {
RenderSettings renderSettings(const RenderCommandSettings& c) {
  RenderSettings r;
  r.width = c.width;
  r.height = c.height;
  r.technique = parseShadowTechnique(c.shadows);
  r.sdf.penumbra = parsePenumbraEstimate(c.penumbra);
  r.sdf.sampling = parseSdfSampling(c.sdfSampling);
  r.sdf.epsilonVoxels = c.epsilon;
  r.sdf.biasVoxels = c.bias;
  r.sdf.minStepVoxels = c.minStep;
  r.sdf.maxStep = c.maxStep;
  r.sdf.maxSteps = c.maxSteps;
  r.sdf.jitter = c.jitter;
  r.sdf.normalOffset = c.normalOffset;
  r.shadowMap.resolution = c.shadowMapRes;
  r.shadowMap.pcfRadius = c.pcfRadius;
  r.shadowMap.depthBiasTexels = c.shadowBias;
  r.taa.enabled = c.taa;
  r.taa.blend = c.taaBlend;
  r.rayTraced.samples = c.samples;
  r.rayTraced.seed = c.pipeline.seed;
  r.pipeline = pipelineSettings(c.pipeline);
  r.validate();
  return r;
}

std::string passTable(const RenderedFrame& f) {
  std::map<std::string, double> ms;
  std::vector<std::string> order;
  for (const auto& [n, t] : f.passMs) {
    if (!ms.count(n)) order.push_back(n);
    ms[n] += t;
  }
  std::string s;
  for (const auto& n : order) s += fmt::format("  {:<28} {:9.2f} ms\n", n, ms[n]);
  return s;
}
} // namespace

int runRender(const RenderCommandSettings& c) {
  checkOutputPath(c.output);
  const fs::path png = c.png.empty() ? fs::path(c.output).replace_extension(".png") : fs::path(c.png);
  checkOutputPath(png.string());
  if (c.frames < 1) throw Error(fmt::format("--frames {} must be at least 1", c.frames));
  if (!(c.fps > 0.0) || !std::isfinite(c.fps)) throw Error(fmt::format("--fps {} must be positive", c.fps));
  const RenderSettings rs = renderSettings(c);
  const Scene scene = loadScene(c.scene);
  if (!scene.hasCamera) throw Error(fmt::format("{}: the scene has no camera to render from", c.scene));
  if (scene.lights.empty()) throw Error(fmt::format("{}: the scene has no light to cast shadows", c.scene));
  const double t0 = c.time - double(c.frames - 1) / c.fps;

  RenderedFrame frame;
  if (rs.technique == ShadowTechnique::RayTraced) {
    spdlog::info("ray tracing {} sample(s) per pixel and light at {}x{} (CPU)", rs.rayTraced.samples, rs.width, rs.height);
    frame = renderRayTraced(scene, c.time, rs);
  } else {
    Bounds bounds;
    for (int f = 0; f < c.frames; ++f) bounds.add(buildSceneGeometry(scene, t0 + f / c.fps).bounds);
    gpu::ContextOptions copt;
    copt.device = c.pipeline.device;
    gpu::VulkanContext ctx(copt);
    Renderer renderer(ctx, scene, bounds, rs);
    if (renderer.sdfPipeline())
      spdlog::info("SDF: coarse {}, fine {}", renderer.sdfPipeline()->coarseSpec().describe(),
                   renderer.sdfPipeline()->fineSpec().describe());
    Progress progress("render", std::uint64_t(c.frames));
    for (int f = 0; f < c.frames; ++f) {
      frame = renderer.renderFrame(t0 + f / c.fps, f + 1 == c.frames);
      progress.add();
    }
    progress.finish();
  }
  fmt::print("{} shadows, {}x{}, frame at t = {} s:\n{}", c.shadows, rs.width, rs.height, c.time, passTable(frame));

  const Image img = composeImage(scene, frame);
  if (c.compare) {
    spdlog::info("ray tracing the truth ({} samples per pixel and light)", rs.rayTraced.samples);
    const RenderedFrame truth = renderRayTraced(scene, c.time, rs);
    const ShadowImageError e = compareWithTruth(scene, frame, truth);
    fmt::print("against ray-traced truth: visibility RMSE {:.4f}, mean |diff| {:.4f} ({} lit pixels); penumbra RMSE "
               "{:.4f} ({} pixels); FLIP {:.4f}\n",
               e.visibilityRmse, e.visibilityMeanAbs, e.pixels, e.penumbraRmse, e.penumbraPixels, e.flip);
    // The visibility error as a picture: red where the frame is too dark, green where it is too bright.
    Image err(rs.width, rs.height);
    std::vector<float> r(frame.gbuffer.pixelCount(), 0.0f), g(r.size(), 0.0f), b(r.size(), 0.0f);
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
      for (std::size_t i = 0; i < r.size(); ++i) {
        const float d = frame.visibility[l][i] - truth.visibility[l][i];
        (d < 0.0f ? r[i] : g[i]) += std::fabs(d);
      }
    err.setChannel("R", std::move(r));
    err.setChannel("G", std::move(g));
    err.setChannel("B", std::move(b));
    const fs::path errPath = fs::path(c.output).replace_extension("").string() + "_error.png";
    writePng(errPath, err);
    fmt::print("wrote the visibility error picture {}\n", errPath.string());
  }
  writeExr(c.output, img);
  writePng(png, displayImage(img));
  fmt::print("wrote {} (channels R, G, B", c.output);
  for (std::size_t l = 0; l < scene.lights.size(); ++l) fmt::print(", {}.V", lightChannelName(scene, l));
  fmt::print(") and {}\n", png.string());
  return 0;
}

} // namespace rtsdf::app
