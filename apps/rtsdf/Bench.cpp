// rtsdf bench: the exact reference against OpenVDB's meshToLevelSet, same voxels and band, one run.
#include "Commands.h"

#include "grid/GridSpec.h"
#include "metrics/FieldError.h"
#include "reference/CoarseReference.h"
#include "reference/OpenVdbLevelSet.h"
#include "sdf/CoarseSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Progress.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

namespace rtsdf::app {
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

std::string cpuName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

} // namespace

namespace {

/// The coarse-SDF suite: GPU pass times per JFA variant beside the CPU jump flooding, the exact EDT of the
/// same seeds and OpenVDB's full-domain meshToSignedDistanceField, at the same voxels.
std::string coarseSuite(const BenchSettings& s) {
  gpu::ContextOptions copt;
  copt.device = s.device;
  copt.validation = false;
  gpu::VulkanContext ctx(copt);
  CoarseSdfBuilder builder(ctx);
  std::string md = fmt::format("GPU: {} ({}). GPU times: median of {} runs after one warm-up, from GPU timestamps. "
                               "CPU times: median of {} runs (OpenVDB: 1 run).\n\n",
                               ctx.info().name, ctx.info().typeName, s.repeats, s.repeats);
  md += "| scene | res | grid | variant | voxelize (ms) | jump flood (ms) | distance (ms) | coarse SDF total (ms) | "
        "CPU jump flood (ms) | exact EDT (ms) | OpenVDB SDF (ms) | coarse / OpenVDB | voxels off vs EDT | max error "
        "(voxels) |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
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
          1e3 * medianSeconds(s.repeats, [&] { jumpFloodCpu(seeds, spec.dims, JfaVariant::OnePlusJfa); });
      const double tVdb = 1e3 * medianSeconds(1, [&] { openvdbSignedDistanceField(geo, spec); });
      for (JfaVariant v : {JfaVariant::Jfa, JfaVariant::OnePlusJfa, JfaVariant::JfaPlusTwo}) {
        CoarseSdfSettings cs;
        cs.variant = v;
        builder.build(corners, spec, cs); // warm-up
        std::vector<double> vox, jfa, dist;
        CoarseSdf last;
        for (int r = 0; r < s.repeats; ++r) {
          last = builder.build(corners, spec, cs);
          vox.push_back(last.passTotal(VoxelizePass::kName));
          jfa.push_back(last.passTotal(JumpFloodPass::kName));
          dist.push_back(last.passTotal(CoarseDistancePass::kName));
        }
        auto med = [](std::vector<double> x) { std::sort(x.begin(), x.end()); return x[x.size() / 2]; };
        const double total = med(vox) + med(jfa) + med(dist);
        const JfaAccuracy acc = compareWithExact(last.nearest, edt, spec.dims);
        md += fmt::format("| {} | {} | {}x{}x{} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {} | {} | {} | {:.3f} | "
                          "{:.4f}% | {:.2f} |\n",
                          fs::path(path).filename().string(), res, spec.dims.x, spec.dims.y, spec.dims.z, toString(v),
                          med(vox), med(jfa), med(dist), total,
                          v == JfaVariant::OnePlusJfa ? fmt::format("{:.1f}", tCpuJfa) : "",
                          v == JfaVariant::OnePlusJfa ? fmt::format("{:.1f}", tEdt) : "",
                          v == JfaVariant::OnePlusJfa ? fmt::format("{:.0f}", tVdb) : "", total / tVdb,
                          100.0 * acc.wrongFraction(), acc.maxError);
      }
    }
  }
  return md;
}

int finishReport(const BenchSettings& s, const std::string& md) {
  fmt::print("{}", md);
  if (!s.output.empty())
    writeFileAtomically(s.output, [&](const fs::path& tmp) {
      std::ofstream out(tmp);
      out << md;
      if (!out) throw Error(fmt::format("{}: cannot write", s.output));
    });
  return 0;
}

} // namespace

int runBench(const BenchSettings& settings) {
  BenchSettings s = settings;
  if (s.scenes.empty())
    s.scenes = {std::string(RTSDF_DATA_DIR) + "/scenes/default.json", std::string(RTSDF_DATA_DIR) + "/scenes/bunny.json"};
  if (!s.output.empty()) checkOutputPath(s.output);

  std::string md;
  const std::time_t now = std::time(nullptr);
  md += fmt::format("Machine: {}, {} hardware threads. Date: {:%Y-%m-%d}.\n\n", cpuName(),
                    std::thread::hardware_concurrency(), fmt::localtime(now));
  if (s.suite == "coarse") {
    md += coarseSuite(s);
    return finishReport(s, md);
  }
  md += fmt::format("Median of {} runs.\n\n", s.repeats);
  md += "| scene | res | grid | band (voxels) | active voxels | exact (s) | OpenVDB meshToLevelSet (s) | "
        "exact / OpenVDB | OpenVDB vs exact: mean / max abs (voxels) | wrong sign |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";

  for (const std::string& path : s.scenes) {
    const Scene scene = loadScene(path);
    const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
    const double band = s.bandFraction * geo.bounds.maxExtent();
    for (int res : s.resolutions) {
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, band);
      spdlog::info("bench {} at {}: {}", path, res, spec.describe());
      ExactSdfOptions opt;
      opt.band = band;
      opt.progress = false;
      openvdb::FloatGrid::Ptr exact, vdb;
      const double tExact = medianSeconds(s.repeats, [&] { exact = exactSignedDistance(geo, spec, opt); });
      const double tVdb = medianSeconds(s.repeats, [&] { vdb = openvdbLevelSet(geo, spec, band); });
      const FieldError err = compareFields(*vdb, *exact);
      const std::string row = fmt::format(
          "| {} | {} | {}x{}x{} | {:.1f} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} / {:.2f} | {:.3f}% |\n",
          fs::path(path).filename().string(), res, spec.dims.x, spec.dims.y, spec.dims.z, band / spec.voxelSize,
          exact->activeVoxelCount(), tExact, tVdb, tExact / tVdb, err.meanAbs, err.maxAbs, 100.0 * err.signErrorRate());
      md += row;
      spdlog::info("exact {:.3f} s, OpenVDB {:.3f} s, ratio {:.2f}", tExact, tVdb, tExact / tVdb);
    }
  }
  return finishReport(s, md);
}

} // namespace rtsdf::app
