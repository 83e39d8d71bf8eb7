#include "suites/SweepJob.h"

#include "suites/SweepPlots.h"
#include "suites/Suites.h"
#include "jobs/JobSupport.h"
#include "scene/SceneLoader.h"
#include "util/AtomicFile.h"
#include "util/Error.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <thread>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

std::string scenePathOf(const SweepJobOptions& o) {
  return o.scene.empty() ? bundledScene("default.json") : o.scene;
}

fs::path outDirOf(const SweepJobOptions& o) {
  return o.outDir.empty() ? fs::path("sweep-" + fs::path(scenePathOf(o)).stem().string()) : o.outDir;
}

std::string seconds(double s) {
  if (s < 90) return fmt::format("{:.0f} s", s);
  return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
}

SweepContext reportContext(const SweepJobOptions& o, const SweepRunOptions& ro, const SweepRunner& runner,
                           std::size_t planned) {
  SweepContext ctx;
  ctx.scene = fs::path(scenePathOf(o)).filename().string();
  ctx.command = o.command;
  ctx.machine = fmt::format("{}, {} hardware threads", cpuName(), std::thread::hardware_concurrency());
  ctx.device = fmt::format("{} ({}, {})", runner.device().name, runner.device().typeName, runner.device().driver);
  ctx.date = fmt::format("{:%Y-%m-%d}", fmt::localtime(std::time(nullptr)));
  ctx.preset = o.preset;
  ctx.errorBand = o.run.errorBand;
  ctx.planned = planned;
  ctx.repeats = o.run.repeats;
  if (runner.measuresShadows()) {
    ctx.shadowWidth = ro.shadowWidth;
    ctx.shadowHeight = ro.shadowHeight;
    ctx.truthSamples = ro.truthSamples;
  }
  return ctx;
}

/// One log line per finished point, with the time the rest should take.
void logPoint(const SweepRecord& r, std::size_t i, std::size_t n, double eta) {
  if (r.ok() && r.point.group == SweepGroup::Storage)
    spdlog::info("[{}/{}] {}: {} active voxels, .vdb {:.2f} MiB vs dense {:.1f} MiB; ETA {}", i + 1, n,
                 r.point.label(), r.maskVoxels, r.vdbBytes / 1048576.0, r.denseBytes / 1048576.0, seconds(eta));
  else if (r.ok())
    spdlog::info("[{}/{}] {}: {:.1f} ms/frame, mean |error| {:.3f} voxels, peak {:.0f} MiB; ETA {}", i + 1, n,
                 r.point.label(), r.frameMs, r.meanAbs, r.peakMiB, seconds(eta));
  else
    spdlog::warn("[{}/{}] {}: could not run: {}; ETA {}", i + 1, n, r.point.label(), r.note, seconds(eta));
}

/// Run the points in order, appending CSV rows as each finishes (an interrupted sweep keeps its points).
void runPoints(SweepRunner& runner, const std::vector<SweepPoint>& plan, int repeats, std::ofstream& csv,
               const fs::path& csvPath, const std::string& stage, const JobControl& control,
               SweepJobResult& result) {
  double totalCost = 0.0, doneCost = 0.0;
  for (const SweepPoint& p : plan) totalCost += p.estimatedCost(repeats);
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < plan.size() && !control.stopping(); ++i) {
    std::vector<SweepRecord> rs;
    try {
      rs = runner.run(plan[i]);
    } catch (const SweepInterrupted&) {
      break;
    }
    for (const SweepRecord& r : rs) csv << csvRow(r) << "\n";
    csv << std::flush;
    if (!csv) throw Error(fmt::format("{}: write failed", csvPath.string()));
    if (!rs.back().ok()) ++result.failed;
    result.records.insert(result.records.end(), rs.begin(), rs.end());
    result.finished = i + 1;
    doneCost += plan[i].estimatedCost(repeats);
    control.report(stage, std::uint64_t(doneCost), std::uint64_t(std::ceil(totalCost)));
    const double elapsed = secondsSince(start);
    logPoint(rs.back(), i, plan.size(), elapsed * (totalCost - doneCost) / std::max(doneCost, 1e-9));
  }
}

} // namespace

void SweepJobOptions::validate() const {
  run.validate();
  const fs::path dir = outDirOf(*this);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw SettingError("output folder", fmt::format("{}: exists and is not a folder", dir.string()));
  if (!dir.parent_path().empty() && !fs::is_directory(dir.parent_path()))
    throw SettingError("output folder", fmt::format("{}: the folder {} does not exist", dir.string(),
                                                    dir.parent_path().string()));
}

SweepJobResult runSweep(const SweepJobOptions& o, const JobControl& control) {
  o.validate();
  const Scene scene = loadScene(scenePathOf(o));
  SweepJobResult result;
  result.dir = outDirOf(o);
  SweepRunOptions ro = o.run;
  ro.stopRequested = [&control] { return control.stopping(); };
  if (o.preset == SweepPreset::Quick) { // a smoke run: small shadow pictures too
    ro.shadowWidth = 160;
    ro.shadowHeight = 90;
  }
  SweepRunner runner(scene, ro);
  const std::vector<SweepPoint> plan = makeSweepPlan(o.preset, runner.animated(), runner.sceneExtent());
  result.planned = plan.size();
  SweepContext ctx = reportContext(o, ro, runner, plan.size());

  fs::create_directories(result.dir);
  const fs::path csvPath = result.dir / "sweep.csv";
  std::ofstream csv(csvPath, std::ios::trunc);
  if (!csv) throw Error(fmt::format("{}: cannot write", csvPath.string()));
  csv << csvHeader() << "\n" << std::flush;
  spdlog::info("sweep '{}' on {}: {} points into {}/ (Ctrl-C stops after the current frame and keeps the finished "
               "points)", toString(o.preset), ctx.scene, plan.size(), result.dir.string());
  runPoints(runner, plan, o.run.repeats, csv, csvPath, fmt::format("sweep {}", toString(o.preset)), control, result);
  csv.close();
  runner.finish();
  // A stop request after the last point stopped nothing.
  result.interrupted = control.stopping() && result.finished < plan.size();
  ctx.interrupted = result.interrupted;
  if (result.interrupted)
    spdlog::warn("sweep interrupted: writing the report of the {} records finished", result.records.size());
  try {
    ctx.plots = writeSweepPlots(result.dir, result.records, ctx.scene);
  } catch (const Error& e) {
    result.plotError = e.what();
  }
  result.plots = ctx.plots.size();
  writeTextAtomically(result.dir / "report.md", markdownReport(ctx, result.records));
  spdlog::info("wrote {}, {} and {} plot(s) in {}", csvPath.filename().string(), "report.md", ctx.plots.size(),
               result.dir.string());
  if (result.failed) spdlog::warn("{} point(s) could not run; report.md says why", result.failed);
  return result;
}

} // namespace rtsdf::bench
