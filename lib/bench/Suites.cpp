// rtsdf bench's suites: the builders against their anchors, same voxels and band, one run.
#include "bench/Suites.h"

#include "bench/FrameSuite.h"

#include "grid/GridSpec.h"
#include "grid/VdbIO.h"
#include "image/ImageIO.h"
#include "jobs/JobSupport.h"
#include "jobs/RenderJob.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "reference/OpenVdbLevelSet.h"
#include "render/RenderPasses.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/CoarseReference.h"
#include "sdf/CoarseSdf.h"
#include "sdf/RefinePasses.h"
#include "sdf/SdfPipeline.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Progress.h"
#include "util/Settings.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <thread>
#include <tuple>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

template <typename F>
double medianSeconds(int repeats, F&& run) {
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

} // namespace

std::string cpuName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

namespace {

/// The median GPU time of s.repeats runs of @a run (each returns its pass's milliseconds), after one run that
/// pays for pipelines and allocations and s.warmUpSeconds of runs for the GPU's clocks.
double warmMedianMs(const BenchOptions& s, const std::function<double()>& run) {
  run();
  warmUpGpu(s.warmUpSeconds, run);
  std::vector<double> t;
  for (int r = 0; r < s.repeats; ++r) t.push_back(run());
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

constexpr std::uint32_t kChunkVoxels[] = {16, 32, 64, 256, 1024, 4096};

/// One row of the coarse suite's chunk table: VoxelizePass's GPU time per kChunkVoxels on one scene and grid.
std::string voxelizeChunkRow(CoarseSdfBuilder& builder, const BenchOptions& s, const std::string& scene, int res,
                             const std::vector<glm::vec4>& corners, const GridSpec& spec) {
  std::string row = fmt::format("| {} | {} |", scene, res);
  for (std::uint32_t c : kChunkVoxels) {
    CoarseSdfSettings cs;
    cs.chunkVoxels = c;
    cs.readNearest = false;
    row += fmt::format(" {:.2f} |", warmMedianMs(s, [&] {
      return builder.build(corners, spec, cs).passTotal(VoxelizePass::kName);
    }));
  }
  return row + "\n";
}

/// The coarse-SDF suite: GPU pass times per coarse method (the exact transform and the jump-flooding variants)
/// beside the CPU jump flooding, the CPU exact EDT of the same seeds and OpenVDB's full-domain
/// meshToSignedDistanceField, at the same voxels; each method's errors against the exact EDT.
std::string coarseSuite(const BenchOptions& s) {
  gpu::ContextOptions copt = deviceContextOptions(s.device);
  copt.validation = false;
  gpu::VulkanContext ctx(copt);
  CoarseSdfBuilder builder(ctx);
  std::string md = fmt::format("GPU: {} ({}). GPU times: median of {} runs after one warm-up and {} s of warm-up "
                               "runs, from GPU timestamps. CPU times: median of {} runs (OpenVDB: 1 run). Transform: "
                               "ExactEdtPass (edt) or JumpFloodPass.\n\n",
                               ctx.info().name, ctx.info().typeName, s.repeats, s.warmUpSeconds, s.repeats);
  md += "| scene | res | grid | method | voxelize (ms) | transform (ms) | distance (ms) | coarse SDF total (ms) | "
        "transform vs 1+jfa | CPU jump flood (ms) | CPU exact EDT (ms) | OpenVDB SDF (ms) | coarse / OpenVDB | voxels "
        "off vs EDT | max error (voxels) |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto med = [](std::vector<double> x) { std::sort(x.begin(), x.end()); return x[x.size() / 2]; };
  std::string chunks = fmt::format("\nVoxelizePass against the voxels each invocation tests (this device's default: "
                                   "{}), GPU ms, median of {} runs after the warm-up:\n\n| scene | res |",
                                   ctx.info().typeName == "cpu" ? gpu::shared::kVoxelizeChunkVoxelsCpu
                                                                : gpu::shared::kVoxelizeChunkVoxelsGpu,
                                   s.repeats);
  for (std::uint32_t c : kChunkVoxels) chunks += fmt::format(" {} |", c);
  chunks += "\n|---|---|";
  for (std::size_t i = 0; i < std::size(kChunkVoxels); ++i) chunks += "---|";
  chunks += "\n";
  for (const std::string& path : s.scenes) {
    const SceneGeometry geo = buildSceneGeometry(loadScene(path), 0.0);
    const auto corners = triangleCorners(geo);
    for (int res : s.resolutions) {
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, 0.05 * geo.bounds.maxExtent());
      spdlog::info("bench coarse {} at {}: {}", path, res, spec.describe());
      const auto seeds = voxelizeCpu(corners, spec);
      std::vector<float> edt;
      const double tEdt = 1e3 * medianSeconds(s.repeats, [&] { edt = exactEdtSquared(seeds, spec.dims); });
      const double tCpuJfa =
          1e3 * medianSeconds(s.repeats, [&] { jumpFloodCpu(seeds, spec.dims, CoarseMethod::OnePlusJfa); });
      const double tVdb = 1e3 * medianSeconds(1, [&] { openvdbSignedDistanceField(geo, spec); });
      struct Row { CoarseMethod method; double vox, transform, dist; JfaAccuracy acc; };
      std::vector<Row> rows;
      for (CoarseMethod m : {CoarseMethod::Edt, CoarseMethod::Jfa, CoarseMethod::OnePlusJfa, CoarseMethod::JfaPlusTwo}) {
        CoarseSdfSettings cs;
        cs.method = m;
        builder.build(corners, spec, cs); // warm-up: pipelines and allocations
        warmUpGpu(s.warmUpSeconds, [&] { builder.build(corners, spec, cs); }); // and the GPU's clocks
        std::vector<double> vox, transform, dist;
        CoarseSdf last;
        for (int r = 0; r < s.repeats; ++r) {
          last = builder.build(corners, spec, cs);
          vox.push_back(last.passTotal(VoxelizePass::kName));
          transform.push_back(last.passTotal(JumpFloodPass::kName) + last.passTotal(ExactEdtPass::kName));
          dist.push_back(last.passTotal(CoarseDistancePass::kName));
        }
        rows.push_back({m, med(vox), med(transform), med(dist), compareWithExact(last.nearest, edt, spec.dims)});
      }
      chunks += voxelizeChunkRow(builder, s, fs::path(path).filename().string(), res, corners, spec);
      const double anchor = rows[2].transform; // 1+jfa, the paper's
      for (const Row& r : rows) {
        const bool first = r.method == CoarseMethod::Edt;
        const double total = r.vox + r.transform + r.dist;
        md += fmt::format("| {} | {} | {}x{}x{} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.3f} | {} | {} | {} | "
                          "{:.3f} | {:.4f}% | {:.2f} |\n",
                          fs::path(path).filename().string(), res, spec.dims.x, spec.dims.y, spec.dims.z,
                          toString(r.method), r.vox, r.transform, r.dist, total, r.transform / anchor,
                          first ? fmt::format("{:.1f}", tCpuJfa) : "", first ? fmt::format("{:.1f}", tEdt) : "",
                          first ? fmt::format("{:.0f}", tVdb) : "", total / tVdb, 100.0 * r.acc.wrongFraction(),
                          r.acc.maxError);
      }
    }
  }
  return md + chunks;
}

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

/// The refinement suite: the paper's tables (ray-trace pass time for x at sizes S and M; band d x rays)
/// with the error against the exact field beside each time, and OpenVDB's meshToLevelSet at the fine
/// resolution and band as the anchor.
std::string refineSuite(const BenchOptions& s) {
  gpu::ContextOptions copt = deviceContextOptions(s.device);
  copt.validation = false;
  gpu::VulkanContext ctx(copt);
  const int frames = 2;
  std::string md = fmt::format("GPU: {} ({}). Each point runs {} frames (static scene) after {} s of warm-up frames "
                               "on a pipeline of its own; times are the last frame's GPU timestamps; errors are after "
                               "the last frame, in fine voxels, over the fine voxels with |exact| <= 0.1 (scene "
                               "units), signs on the surface excluded.\n\n",
                               ctx.info().name, ctx.info().typeName, frames, s.warmUpSeconds);
  for (const std::string& path : s.scenes) {
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
        ps.rays = x;
        spdlog::info("bench refine {} d={} x={}", name, d, x);
        const RefinePoint r = runRefinePoint(ctx, scene, geo, ps, frames, 0.1, s.warmUpSeconds);
        md += fmt::format("| {} | {} | {} | {:.1f} | {:.3f} / {:.2f} | {:.3f}% |\n", d >= 1e3 ? "inf" : fmt::format("{}", d), x,
                          r.mask, r.refineMs, r.error.meanAbs, r.error.maxAbs, 100.0 * r.error.signErrorRate());
      }
    }
    md += "\n";
  }
  return md;
}

/// Per-pass GPU times (median over frames after two warm-up frames) of one technique, as table rows; the
/// last frame is kept for its error.
struct TechniqueTiming {
  std::string rows;
  double totalMs = 0.0;
  RenderedFrame last;
};

TechniqueTiming timeTechnique(const gpu::VulkanContext& ctx, const Scene& scene, const RenderSettings& rs,
                              const std::string& name, int frames, double warmUpSeconds) {
  const Bounds bounds = buildSceneGeometry(scene, 0.0).bounds;
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
    t.last = r.renderFrame(0.0, f + 1 == frames + 2);
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

/// The renderer suite: per-pass GPU times of SDF shadows and shadow maps at 640x360 and 1280x720 (median
/// over frames after warm-up), their image error against the ray-traced truth of the same frame, and the
/// ray tracer's time per sample count, to find the samples at which it reaches the SDF's error.
std::string renderSuite(const BenchOptions& s) {
  gpu::VulkanContext ctx(deviceContextOptions(s.device));
  std::string md = fmt::format(
      "GPU: {} ({}). GPU pass times: median over {} frames after {} warm-up frames and {} s of frames on a renderer "
      "of its own (GPU timestamps). Error against "
      "the ray-traced truth ({} samples per pixel) of the same frame: visibility mean |diff| over lit surfaces, "
      "RMSE in the truth's penumbra (0.02 < V < 0.98), mean |diff| in its umbra (V < 0.02), mean LDR-FLIP of the "
      "pictures.\n\n",
      ctx.info().name, ctx.info().driver, 4, 2, s.warmUpSeconds, 1024);
  for (const std::string& path : s.scenes) {
    const Scene scene = loadScene(path);
    if (!scene.hasCamera || scene.lights.empty()) continue;
    for (const glm::ivec2 size : {glm::ivec2(640, 360), glm::ivec2(1280, 720)})
      md += renderSize(ctx, s, path, scene, size);
  }
  return md;
}

/// The exact SDF and OpenVDB's meshToLevelSet of @a geo on the same voxels and band, each timed (median of the
/// suite's repeats).
struct ExactAndOpenVdb {
  openvdb::FloatGrid::Ptr exact, openVdb;
  double exactSeconds = 0.0, openVdbSeconds = 0.0;
};
ExactAndOpenVdb timeExactAndOpenVdb(const BenchOptions& s, const SceneGeometry& geo, const GridSpec& spec,
                                    double band) {
  ExactSdfOptions opt;
  opt.band = band;
  opt.progress = false;
  ExactAndOpenVdb r;
  r.exactSeconds = medianSeconds(s.repeats, [&] { r.exact = exactSignedDistance(geo, spec, opt); });
  r.openVdbSeconds = medianSeconds(s.repeats, [&] { r.openVdb = openvdbLevelSet(geo, spec, band); });
  return r;
}

/// The reference suite: the exact SDF against OpenVDB's meshToLevelSet, same voxels and band.
std::string referenceSuite(const BenchOptions& s) {
  std::string md = fmt::format("Median of {} runs.\n\n", s.repeats);
  md += "| scene | res | grid | band (voxels) | active voxels | exact (s) | OpenVDB meshToLevelSet (s) | "
        "exact / OpenVDB | OpenVDB vs exact: mean / max abs (voxels) | wrong sign |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& path : s.scenes) {
    const SceneGeometry geo = buildSceneGeometry(loadScene(path), 0.0);
    const double band = s.bandFraction * geo.bounds.maxExtent();
    for (int res : s.resolutions) {
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, band);
      spdlog::info("bench {} at {}: {}", path, res, spec.describe());
      const ExactAndOpenVdb r = timeExactAndOpenVdb(s, geo, spec, band);
      const double tExact = r.exactSeconds, tVdb = r.openVdbSeconds;
      const FieldError err = compareFields(*r.openVdb, *r.exact);
      md += fmt::format("| {} | {} | {}x{}x{} | {:.1f} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} / {:.2f} | {:.3f}% |\n",
                        fs::path(path).filename().string(), res, spec.dims.x, spec.dims.y, spec.dims.z,
                        band / spec.voxelSize, r.exact->activeVoxelCount(), tExact, tVdb, tExact / tVdb, err.meanAbs,
                        err.maxAbs, 100.0 * err.signErrorRate());
      spdlog::info("exact {:.3f} s, OpenVDB {:.3f} s, ratio {:.2f}", tExact, tVdb, tExact / tVdb);
    }
  }
  return md;
}

/// The open-mesh case: the bunny split in four three times (235k triangles) with 12 small holes cut, the scan with
/// holes users bring. Exact (the rim-only winding number) against OpenVDB at the same voxels and band, a
/// 3-voxel band and the suite's band fraction, and against the winding number everywhere (the sign rule before
/// rim-only), whose signs it must keep.
std::string openMeshCase(const BenchOptions& s) {
  Scene scene = loadScene(bundledMesh("bunny.obj"));
  const Bounds bounds = buildSceneGeometry(scene, 0.0).bounds;
  scene.meshes[0] = cutHoles(subdivideMesh(scene.meshes[0], 3), 12, float(0.03 * bounds.maxExtent()));
  scene.meshReports[0] = validateMesh(scene.meshes[0]);
  const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
  std::string md = fmt::format("\nOpen mesh: the bunny split in four 3 times with 12 holes cut ({} triangles, {} "
                               "boundary edges). exact: the default sign rule (winding number on the rim only); "
                               "winding everywhere: the rule before it, one run; wrong sign: exact vs that.\n\n",
                               geo.triangleCount(), scene.meshReports[0].boundaryEdges);
  md += "| res | band (voxels) | active voxels | exact (s) | OpenVDB (s) | exact / OpenVDB | winding everywhere (s) | "
        "wrong sign vs winding everywhere | OpenVDB vs exact: mean / max abs (voxels) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (int res : s.resolutions)
    for (double bandVoxels : {3.0, s.bandFraction * res}) {
      const double band = bandVoxels * bounds.maxExtent() / res;
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, band);
      const ExactAndOpenVdb r = timeExactAndOpenVdb(s, geo, spec, band);
      const openvdb::FloatGrid::Ptr& exact = r.exact;
      const double tExact = r.exactSeconds, tVdb = r.openVdbSeconds;
      ExactSdfOptions opt;
      opt.band = band;
      opt.progress = false;
      opt.sign = SignMethod::WindingNumber;
      openvdb::FloatGrid::Ptr winding;
      const double tWinding = medianSeconds(1, [&] { winding = exactSignedDistance(geo, spec, opt); });
      const FieldError signs = compareFields(*exact, *winding), err = compareFields(*r.openVdb, *exact);
      md += fmt::format("| {} | {:.1f} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} | {:.4f}% | {:.3f} / {:.2f} |\n", res,
                        bandVoxels, exact->activeVoxelCount(), tExact, tVdb, tExact / tVdb, tWinding,
                        100.0 * signs.signErrorRate(), err.meanAbs, err.maxAbs);
      spdlog::info("open mesh at {}, band {:.1f} voxels: exact {:.3f} s, OpenVDB {:.3f} s, winding {:.3f} s, {} wrong "
                   "signs", res, bandVoxels, tExact, tVdb, tWinding, signs.signMismatches);
    }
  return md;
}

} // namespace

std::pair<int, int> frameSizeResolutions(FrameSize size) {
  switch (size) {
  case FrameSize::S: return {64, 128};
  case FrameSize::L: return {256, 512};
  case FrameSize::M: break;
  }
  return {128, 256};
}

void BenchOptions::validate() const {
  requireInRange("repeats", repeats, 1, 100);
  requireInRange("frames", frames, 1, 100000);
  requireInRange("rays", rays, 0, 1024);
  if (suite == BenchSuite::Frame && scenes.size() > 1)
    throw SettingError("scenes", fmt::format("the frame suite runs on one scene, not {}", scenes.size()));
  requireInRange("band fraction", bandFraction, 1e-6, 10.0);
  requireInRange("warm-up seconds", warmUpSeconds, 0.0, 60.0);
  for (int r : resolutions) requireInRange("resolution", r, 1, GridSpec::kMaxResolution);
}

std::string runBenchSuite(const BenchOptions& options, const JobControl& control) {
  options.validate();
  BenchOptions s = options;
  if (s.scenes.empty()) s.scenes = {bundledScene("default.json"), bundledScene("bunny.json")};
  if (s.suite == BenchSuite::Frame) s.scenes.resize(1);
  const std::vector<fs::path> inputs(s.scenes.begin(), s.scenes.end());
  if (!s.output.empty()) checkOutputPath(s.output, {}, inputs);
  if (!s.csv.empty()) checkOutputPath(s.csv, ".csv", inputs);
  std::string md = fmt::format("Machine: {}, {} hardware threads. Date: {:%Y-%m-%d}.\n\n", cpuName(),
                               std::thread::hardware_concurrency(), fmt::localtime(std::time(nullptr)));
  control.checkStop();
  switch (s.suite) {
  case BenchSuite::Coarse: md += coarseSuite(s); break;
  case BenchSuite::Refine: md += refineSuite(s); break;
  case BenchSuite::Render: md += renderSuite(s); break;
  case BenchSuite::Frame: {
    const std::vector<FrameRow> rows = runFrames(s, control);
    md += frameReport(s, rows);
    if (!s.csv.empty()) writeTextAtomically(s.csv, frameCsv(rows));
    break;
  }
  case BenchSuite::Reference:
    md += referenceSuite(s);
    if (options.scenes.empty()) md += openMeshCase(s);
    break;
  }
  if (!s.output.empty()) writeTextAtomically(s.output, md);
  return md;
}

} // namespace rtsdf::bench
