#include "jobs/RenderJob.h"

#include "gpu/VulkanContext.h"
#include "image/ImageIO.h"
#include "jobs/JobSupport.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/AtomicFile.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <map>

namespace rtsdf {
namespace fs = std::filesystem;

RenderSettings RenderJobOptions::defaultRenderSettings() {
  return RenderSettings{};
}

void RenderJobOptions::validate() const {
  validateKnobs(*this);
  render.validate();
}

std::string RenderJobResult::passTable() const {
  std::map<std::string, double> ms;
  std::vector<std::string> order;
  for (const auto& [n, t] : frame.passMs) {
    if (!ms.count(n)) order.push_back(n);
    ms[n] += t;
  }
  std::string s;
  for (const auto& n : order) s += fmt::format("  {:<28} {:9.2f} ms\n", n, ms[n]);
  return s;
}

namespace {

RenderedFrame renderOnGpu(const RenderJobOptions& o, const Scene& scene, RenderJobResult& result,
                          const JobControl& control) {
  const double t0 = o.time - double(o.frames - 1) / o.fps;
  Bounds bounds;
  for (int f = 0; f < o.frames; ++f) bounds.add(buildSceneGeometry(scene, t0 + f / o.fps).bounds);
  return runOnDevice(deviceContextOptions(o.device), [&](const gpu::VulkanContext& ctx) {
    Renderer renderer(ctx, scene, bounds, o.render, t0);
    if (const SdfPipeline* sdf = renderer.sdfPipeline())
      result.sdfGrids = fmt::format("coarse {}, fine {}", sdf->coarseSpec().describe(), sdf->fineSpec().describe());
    else if (const CascadeSet* levels = renderer.cascades())
      result.sdfGrids = fmt::format("{} cascade levels around the camera, level 0: coarse {}, fine {}",
                                    levels->levels(), levels->level(0).coarseSpec().describe(),
                                    levels->level(0).fineSpec().describe());
    if (!result.sdfGrids.empty()) spdlog::info("SDF: {}", result.sdfGrids);
    RenderedFrame frame;
    std::uint64_t cut = 0;
    for (int f = 0; f < o.frames; ++f) {
      control.checkStop();
      frame = renderer.renderFrame(t0 + f / o.fps, f + 1 == o.frames);
      cut += frame.sdf.cutVoxels;
      control.report("render", std::uint64_t(f + 1), std::uint64_t(o.frames));
    }
    warnOfCutWalks(cut, ctx.info().name);
    return frame;
  });
}

/// The visibility error as a picture: red where the frame is too dark, green where it is too bright.
Image visibilityErrorImage(const Scene& scene, const RenderedFrame& frame, const RenderedFrame& truth) {
  Image err(frame.gbuffer.width, frame.gbuffer.height);
  std::vector<float> r(frame.gbuffer.pixelCount(), 0.0f), g(r.size(), 0.0f), b(r.size(), 0.0f);
  for (std::size_t l = 0; l < scene.lights.size(); ++l)
    for (std::size_t i = 0; i < r.size(); ++i) {
      const float d = frame.visibility[l][i] - truth.visibility[l][i];
      (d < 0.0f ? r[i] : g[i]) += std::fabs(d);
    }
  err.setChannel("R", std::move(r));
  err.setChannel("G", std::move(g));
  err.setChannel("B", std::move(b));
  return err;
}

/// The truth a picture is compared with: the ray tracer at the picture's settings. A ray-traced picture gets
/// kTruthSampleFactor times its samples and another seed (an independent stream of rays), so that its
/// comparison measures its own noise: with the truth's, the squared error the comparison reports is the
/// picture's plus at most a quarter of it (the variance of a pixel's estimate falls at least as 1 / samples).
constexpr int kTruthSampleFactor = 4;
RenderSettings truthSettings(const RenderSettings& picture) {
  RenderSettings truth = picture;
  if (picture.technique == ShadowTechnique::RayTraced) {
    truth.rayTraced.samples = picture.rayTraced.samples * kTruthSampleFactor;
    truth.rayTraced.seed = picture.rayTraced.seed + 1;
  }
  return truth;
}

} // namespace

RenderJobResult renderScene(const RenderJobOptions& o, const JobControl& control) {
  o.validate();
  const Scene scene = loadScene(o.scene, o.meshLoad);
  if (!scene.hasCamera) throw Error(fmt::format("{}: the scene has no camera to render from", o.scene));
  if (scene.lights.empty()) throw Error(fmt::format("{}: the scene has no light to cast shadows", o.scene));
  RenderJobResult result;
  if (o.render.technique == ShadowTechnique::RayTraced) {
    spdlog::info("ray tracing {} sample(s) per pixel and light at {}x{} (CPU)", o.render.rayTraced.samples,
                 o.render.width, o.render.height);
    result.frame = renderRayTraced(scene, o.time, o.render, &control);
  } else {
    result.frame = renderOnGpu(o, scene, result, control);
  }
  result.image = composeImage(scene, result.frame);
  if (o.compare) {
    const RenderSettings ts = truthSettings(o.render);
    spdlog::info("ray tracing the truth ({} samples per pixel and light, seed {})", ts.rayTraced.samples,
                 ts.rayTraced.seed);
    const RenderedFrame truth = renderRayTraced(scene, o.time, ts, &control);
    result.error = compareWithTruth(scene, result.frame, truth);
    result.errorImage = visibilityErrorImage(scene, result.frame, truth);
    result.compared = true;
  }
  return result;
}

RenderOutputs RenderOutputs::forExr(const fs::path& exr, const fs::path& png) {
  RenderOutputs o;
  o.exr = exr;
  o.png = png.empty() ? fs::path(exr).replace_extension(".png") : png;
  o.errorPng = fs::path(exr).replace_extension("").string() + "_error.png";
  return o;
}

void RenderOutputs::check(const std::vector<fs::path>& inputs) const {
  checkOutputPath(exr, ".exr", inputs);
  checkOutputPath(png, ".png", inputs);
  auto same = [](const fs::path& a, const fs::path& b) {
    std::error_code ea, eb;
    const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
    return ea || eb ? a == b : ca == cb;
  };
  if (same(png, exr) || same(png, errorPng))
    throw Error(fmt::format("{}: the PNG would replace another output of this render (the EXR is {})", png.string(),
                            exr.string()));
}

void writeRender(const RenderJobResult& result, const RenderOutputs& outputs) {
  std::vector<fs::path> written;
  try {
    if (result.compared) {
      writePng(outputs.errorPng, result.errorImage);
      written.push_back(outputs.errorPng);
    }
    writeExr(outputs.exr, result.image);
    written.push_back(outputs.exr);
    writePng(outputs.png, displayImage(result.image));
  } catch (...) {
    std::error_code ec;
    for (const fs::path& p : written) fs::remove(p, ec);
    throw;
  }
}

} // namespace rtsdf
