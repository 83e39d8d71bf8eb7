// `rtsdf bench --suite coarse`: the coarse SDF's GPU passes per method against the CPU transforms and OpenVDB.
#include "suites/SuiteTables.h"

#include "grid/GridSpec.h"
#include "jobs/JobSupport.h"
#include "reference/OpenVdbLevelSet.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/coarse/CoarseCpu.h"
#include "sdf/coarse/CoarseSdf.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <filesystem>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

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

/// The coarse suite's tables on @a ctx.
std::string coarseTables(const gpu::VulkanContext& ctx, const BenchOptions& s, const JobControl& control) {
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
  JobPoll poll(&control, "coarse suite", s.scenes.size() * s.resolutions.size());
  for (const std::string& path : s.scenes) {
    const SceneGeometry geo = buildSceneGeometry(loadScene(path), 0.0);
    const auto corners = triangleCorners(geo);
    for (int res : s.resolutions) {
      control.checkStop();
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
      poll.done();
    }
  }
  return md + chunks;
}

} // namespace

std::string coarseSuite(const BenchOptions& s, const JobControl& control) {
  return runOnDevice(deviceContextOptions(s.device),
                     [&](const gpu::VulkanContext& ctx) { return coarseTables(ctx, s, control); });
}

} // namespace rtsdf::bench
