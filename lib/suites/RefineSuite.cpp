// `rtsdf bench --suite refine`: the paper's refinement tables, the upsample and volume fill kernels.
#include "suites/SuiteTables.h"

#include "grid/GridSpec.h"
#include "grid/VdbIO.h"
#include "jobs/JobSupport.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "reference/OpenVdbLevelSet.h"
#include "render/RenderPasses.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/SdfPipeline.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <tuple>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

/// Time and error of one pipeline configuration: `frames` frames accumulated; the last frame's GPU passes,
/// and the fine field against the exact one over the band (|exact| <= d) after the last frame.
struct RefinePoint {
  double refineMs = 0.0, totalMs = 0.0, hostMs = 0.0;
  std::uint64_t mask = 0;
  FieldError error;
};

RefinePoint runRefinePoint(const gpu::VulkanContext& ctx, const Scene& scene, const SceneGeometry& geo,
                           const PipelineSettings& ps, int frames, double errorBand, double warmUpSeconds) {
  // The paper's tables time its frame, every masked voxel refined (a static incremental frame refines none).
  PipelineSettings full = ps;
  full.fullRecompute = true;
  warmUpPipeline(ctx, scene, geo.bounds, full, warmUpSeconds);
  SdfPipeline pipe(ctx, scene, geo.bounds, full);
  FrameStats st;
  for (int f = 0; f < frames; ++f) st = pipe.runFrame(0.0);
  RefinePoint r;
  r.refineMs = st.refineMs();
  for (const auto& [n, ms] : st.passMs) r.totalMs += ms;
  r.hostMs = st.hostMs;
  r.mask = st.maskFineVoxels;
  ExactSdfOptions eo;
  eo.band = errorBand;
  eo.progress = false;
  const auto exact = exactSignedDistance(geo, pipe.fineSpec(), eo);
  const auto fine = denseToLevelSet(pipe.fineField(), pipe.fineSpec(), float(errorBand));
  r.error = compareFields(*exact, *fine);
  return r;
}

/// UpsamplePass at sizes S and M: one voxel per invocation against runs along z, on the same coarse SDF and
/// grids as the pipeline's (median GPU time of s.repeats after a warm-up), and whether their outputs agree.
std::string upsampleTable(const gpu::VulkanContext& ctx, const SceneGeometry& geo, const BenchOptions& s) {
  std::string md = "| size | coarse/fine | fine grid | per voxel (ms) | runs of " +
                   std::to_string(RTSDF_UPSAMPLE_RUN_LENGTH) + " along z (ms) | runs / per voxel | max difference |\n"
                   "|---|---|---|---|---|---|---|\n";
  CoarseSdfBuilder builder(ctx);
  const UpsamplePass perVoxel(ctx, UpsamplePass::Kernel::PerVoxel), runs(ctx, UpsamplePass::Kernel::Runs);
  gpu::GpuProfiler profiler(ctx);
  for (const auto& [size, coarseRes, fineRes] : {std::tuple<const char*, int, int>{"S", 64, 128}, {"M", 128, 256}}) {
    PipelineSettings ps;
    ps.coarseRes = coarseRes;
    ps.fineRes = fineRes;
    ps.band = 0.1; // the band of the recorded figures (docs/results.md), in scene units
    const auto [coarse, fine] = pipelineGrids(geo.bounds, ps);
    builder.build(geo, coarse, {});
    const GridSpec c = coarse.inFrame(geo.origin), f = fine.inFrame(geo.origin);
    const gpu::shared::RefineParams p = refineGridParams(c, f); // band 0: every fine voxel is written
    const std::vector<int> fineToCoarse = maskCoarseOfFine(c, f);
    gpu::Buffer table;
    gpu::reserveAndUpload(ctx, table, fineToCoarse.data(), fineToCoarse.size() * sizeof(int),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "fine-to-coarse table");
    // Band 0: no brick slot is read; the binding still needs a buffer.
    const gpu::Buffer none(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "no bricks");
    std::vector<float> out[2];
    double ms[2];
    int k = 0;
    for (const UpsamplePass* pass : {&perVoxel, &runs}) {
      gpu::Buffer buf;
      gpu::reserve(ctx, buf, f.voxelCount() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device,
                   "fine SDF");
      ms[k] = warmMedianMs(s, [&] {
        gpu::CommandBuffer cmd(ctx);
        profiler.reset(cmd.handle());
        pass->execute(cmd.handle(), &profiler, {builder.distanceBuffer(), table, none}, {buf}, p);
        cmd.submitAndWait();
        return passTotal(profiler.results(), UpsamplePass::kName);
      });
      out[k].resize(f.voxelCount());
      gpu::download(ctx, buf, out[k].data(), out[k].size() * 4);
      ++k;
    }
    float maxDiff = 0.0f;
    for (std::size_t i = 0; i < out[0].size(); ++i) maxDiff = std::max(maxDiff, std::fabs(out[0][i] - out[1][i]));
    md += fmt::format("| {} | {}/{} | {}x{}x{} | {:.1f} | {:.1f} | {:.3f} | {:g} |\n", size, coarseRes, fineRes,
                      f.dims.x, f.dims.y, f.dims.z, ms[0], ms[1], ms[1] / ms[0], maxDiff);
  }
  return md;
}

/// VolumeFillPass at sizes S and M: the fine SDF into the shading's 3D texture by a copy command and by a compute
/// shader (median GPU time of s.repeats after the warm-up), and whether the two textures agree bit for bit.
std::string volumeFillTable(const gpu::VulkanContext& ctx, const SceneGeometry& geo, const BenchOptions& s) {
  if (!gpu::SampledVolume::storageSupported(ctx)) return "(this device cannot store to R32F 3D textures)\n";
  std::string md = "| size | fine grid | copy command (ms) | compute shader (ms) | compute / copy | textures differ |\n"
                   "|---|---|---|---|---|---|\n";
  const VolumeFillPass fill(ctx);
  gpu::GpuProfiler profiler(ctx);
  for (const auto& [size, coarseRes, fineRes] : {std::tuple<const char*, int, int>{"S", 64, 128}, {"M", 128, 256}}) {
    PipelineSettings ps;
    ps.coarseRes = coarseRes;
    ps.fineRes = fineRes;
    ps.band = 0.1; // the band of the recorded figures (docs/results.md), in scene units
    const GridSpec f = pipelineGrids(geo.bounds, ps).second;
    std::vector<float> field(f.voxelCount());
    for (std::size_t i = 0; i < field.size(); ++i) field[i] = float(i % 1021) * 0.01f - 5.0f;
    gpu::Buffer src, back;
    gpu::reserveAndUpload(ctx, src, field.data(), field.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "fine SDF");
    gpu::reserve(ctx, back, field.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "back");
    const gpu::SampledVolume texture(ctx, glm::uvec3(f.dims), "fine SDF texture");
    double ms[2];
    std::size_t differ = 0;
    for (int k = 0; k < 2; ++k) {
      const auto method = k ? VolumeFillPass::Method::Compute : VolumeFillPass::Method::Transfer;
      ms[k] = warmMedianMs(s, [&] {
        gpu::CommandBuffer cmd(ctx);
        profiler.reset(cmd.handle());
        fill.execute(cmd.handle(), &profiler, {src}, {texture}, method);
        cmd.submitAndWait();
        return passTotal(profiler.results(), VolumeFillPass::kName);
      });
      gpu::CommandBuffer cmd(ctx);
      texture.copyTo(cmd.handle(), back);
      cmd.submitAndWait();
      std::vector<float> out(field.size());
      gpu::download(ctx, back, out.data(), out.size() * 4);
      for (std::size_t i = 0; i < out.size(); ++i) differ += std::memcmp(&out[i], &field[i], 4) != 0;
    }
    md += fmt::format("| {} | {}x{}x{} | {:.2f} | {:.2f} | {:.3f} | {} |\n", size, f.dims.x, f.dims.y, f.dims.z, ms[0],
                      ms[1], ms[1] / ms[0], differ);
  }
  return md;
}

/// The refine suite's tables on @a ctx.
std::string refineTables(const gpu::VulkanContext& ctx, const BenchOptions& s, const JobControl& control) {
  const int frames = 2;
  std::string md = fmt::format("GPU: {} ({}). Each point runs {} frames (static scene) after {} s of warm-up frames "
                               "on a pipeline of its own; times are the last frame's GPU timestamps; errors are after "
                               "the last frame, in fine voxels, over the fine voxels with |exact| <= 0.1 (scene "
                               "units), signs on the surface excluded.\n\n",
                               ctx.info().name, ctx.info().typeName, frames, s.warmUpSeconds);
  // Progress by the tables' points: sizes S and M x 8 modes, then 5 bands x 4 ray counts per scene.
  constexpr std::size_t kPointsPerScene = 2 * 8 + 5 * 4;
  JobPoll poll(&control, "refine suite", kPointsPerScene * s.scenes.size());
  for (const std::string& path : s.scenes) {
    control.checkStop();
    const Scene scene = loadScene(path);
    const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
    const std::string name = fs::path(path).filename().string();
    md += fmt::format("### {}: UpsamplePass\n\n", name) + upsampleTable(ctx, geo, s) + "\n";
    md += fmt::format("### {}: the fine SDF into the shading's 3D texture (FineSdfTextureCopy)\n\n", name) +
          volumeFillTable(ctx, geo, s) + "\n";
    md += fmt::format("### {}: sizes x rays (d = 0.1, alpha = 0.95, exact coarse transform)\n\n", name);
    md += "| size | coarse/fine | mode | x | mask voxels | refinement pass (ms) | all passes (ms) | host CPU (ms) | "
          "mean / max abs error | wrong sign | OpenVDB meshToLevelSet (ms) | refine / OpenVDB |\n";
    md += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [size, coarse, fine] : {std::tuple<const char*, int, int>{"S", 64, 128}, {"M", 128, 256}}) {
      PipelineSettings ps;
      ps.coarseRes = coarse;
      ps.fineRes = fine;
      ps.band = 0.1; // d = 0.1 scene units, as the table's title says
      // The anchor: OpenVDB's narrow band at the fine voxels and the same band.
      const GridSpec fineSpec = pipelineGrids(geo.bounds, ps).second;
      const double tVdb = 1e3 * medianSeconds(1, [&] { openvdbLevelSet(geo, fineSpec, ps.band); });
      // Closest mode with each search side by side (the same distances; cell search walks once per box of voxels).
      struct Mode { RefineMode mode; int rays; ClosestSearch search; };
      for (const Mode m : {Mode{RefineMode::Rays, 0, {}}, Mode{RefineMode::Rays, 1, {}}, Mode{RefineMode::Rays, 5, {}},
                           Mode{RefineMode::Rays, 10, {}}, Mode{RefineMode::Closest, 0, ClosestSearch::Voxel},
                           Mode{RefineMode::Closest, 0, ClosestSearch::Cell},
                           Mode{RefineMode::Closest, 1, ClosestSearch::Voxel},
                           Mode{RefineMode::Closest, 1, ClosestSearch::Cell}}) {
        ps.mode = m.mode;
        ps.rays = m.rays;
        ps.closestSearch = m.search;
        const std::string mode = m.mode == RefineMode::Closest
                                     ? fmt::format("closest ({})", toString(m.search))
                                     : std::string(toString(m.mode));
        spdlog::info("bench refine {} {} {} x={}", name, size, mode, m.rays);
        const RefinePoint r = runRefinePoint(ctx, scene, geo, ps, frames, 0.1, s.warmUpSeconds);
        poll.done();
        md += fmt::format("| {} | {}/{} | {} | {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.3f} / {:.2f} | {:.3f}% | {:.0f} | "
                          "{:.2f} |\n",
                          size, coarse, fine, mode, m.rays, r.mask, r.refineMs, r.totalMs, r.hostMs,
                          r.error.meanAbs, r.error.maxAbs, 100.0 * r.error.signErrorRate(), tVdb, r.refineMs / tVdb);
      }
    }
    md += fmt::format("\n### {}: band d x rays at size S (64/128)\n\n", name);
    md += "| d | x | mask voxels | RayRefinePass (ms) | mean / max abs error | wrong sign |\n|---|---|---|---|---|---|\n";
    for (double d : {0.01, 0.05, 0.1, 0.5, 1e3}) {
      for (int x : {1, 5, 10, 15}) {
        PipelineSettings ps;
        ps.coarseRes = 64;
        ps.fineRes = 128;
        ps.band = d;
        ps.mode = RefineMode::Rays; // the paper's table: rays mode
        ps.rays = x;
        spdlog::info("bench refine {} d={} x={}", name, d, x);
        const RefinePoint r = runRefinePoint(ctx, scene, geo, ps, frames, 0.1, s.warmUpSeconds);
        poll.done();
        md += fmt::format("| {} | {} | {} | {:.1f} | {:.3f} / {:.2f} | {:.3f}% |\n", d >= 1e3 ? "inf" : fmt::format("{}", d), x,
                          r.mask, r.refineMs, r.error.meanAbs, r.error.maxAbs, 100.0 * r.error.signErrorRate());
      }
    }
    md += "\n";
  }
  return md;
}

} // namespace

std::string refineSuite(const BenchOptions& s, const JobControl& control) {
  return runOnDevice(deviceContextOptions(s.device),
                     [&](const gpu::VulkanContext& ctx) { return refineTables(ctx, s, control); });
}

} // namespace rtsdf::bench
