// rtsdf bench --sweep: the speed/accuracy trade of one scene in one command.
#include "Commands.h"

#include "bench/Sweep.h"
#include "bench/SweepPlots.h"
#include "bench/SweepRunner.h"
#include "scene/SceneLoader.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Progress.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <thread>

namespace rtsdf::app {
namespace fs = std::filesystem;
using namespace rtsdf::bench;

namespace {

std::atomic<bool> gStop{false};

extern "C" void onInterrupt(int) {
  // The first Ctrl-C asks the sweep to stop after the current frame; a second one ends it at once.
  if (gStop.exchange(true)) {
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
  }
}

std::string seconds(double s) {
  if (s < 90) return fmt::format("{:.0f} s", s);
  return fmt::format("{:.0f} min {:02.0f} s", std::floor(s / 60), std::fmod(s, 60));
}

/// Restores the previous SIGINT handler when the sweep ends.
struct InterruptGuard {
  using Handler = void (*)(int);
  Handler previous;
  InterruptGuard() : previous(std::signal(SIGINT, onInterrupt)) { gStop = false; }
  ~InterruptGuard() { std::signal(SIGINT, previous); }
};

} // namespace

int runSweep(const BenchSettings& s) {
  const SweepPreset preset = parseSweepPreset(s.sweep);
  if (s.scenes.size() > 1) throw Error("--sweep runs on one scene (give one scene or mesh)");
  const std::string scenePath =
      s.scenes.empty() ? std::string(RTSDF_DATA_DIR) + "/scenes/default.json" : s.scenes.front();
  const Scene scene = loadScene(scenePath);
  const std::string name = fs::path(scenePath).stem().string();
  const fs::path dir = s.outDir.empty() ? fs::path("sweep-" + name) : fs::path(s.outDir);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw Error(fmt::format("--out {}: exists and is not a folder", dir.string()));
  if (!dir.parent_path().empty() && !fs::is_directory(dir.parent_path()))
    throw Error(fmt::format("--out {}: the folder {} does not exist", dir.string(), dir.parent_path().string()));

  SweepRunOptions ro;
  ro.device = s.device;
  ro.errorBand = s.errorBand;
  ro.shadows = s.shadows;
  ro.truthSamples = s.truthSamples;
  ro.repeats = s.repeats;
  if (preset == SweepPreset::Quick) {
    ro.shadowWidth = 160;
    ro.shadowHeight = 90;
  }
  ro.stopRequested = [] { return gStop.load(); };
  InterruptGuard guard;
  SweepRunner runner(scene, ro);
  const std::vector<SweepPoint> plan = makeSweepPlan(preset, runner.animated(), runner.sceneExtent());

  fs::create_directories(dir);
  const fs::path csvPath = dir / "sweep.csv";
  // Rows are appended and flushed as points finish, so an interrupted sweep keeps its points.
  std::ofstream csv(csvPath, std::ios::trunc);
  if (!csv) throw Error(fmt::format("{}: cannot write", csvPath.string()));
  csv << csvHeader() << "\n" << std::flush;

  SweepContext ctx;
  ctx.scene = fs::path(scenePath).filename().string();
  ctx.command = s.command;
  ctx.machine = fmt::format("{}, {} hardware threads", cpuName(), std::thread::hardware_concurrency());
  ctx.device = fmt::format("{} ({}, {})", runner.device().name, runner.device().typeName, runner.device().driver);
  ctx.date = fmt::format("{:%Y-%m-%d}", fmt::localtime(std::time(nullptr)));
  ctx.preset = preset;
  ctx.errorBand = s.errorBand;
  ctx.planned = plan.size();
  ctx.repeats = s.repeats;
  if (runner.measuresShadows()) {
    ctx.shadowWidth = ro.shadowWidth;
    ctx.shadowHeight = ro.shadowHeight;
    ctx.truthSamples = ro.truthSamples;
  }

  double totalCost = 0.0;
  for (const SweepPoint& p : plan) totalCost += p.estimatedCost(s.repeats);
  spdlog::info("sweep '{}' on {}: {} points into {}/ (Ctrl-C stops after the current frame and keeps the finished "
               "points)",
               toString(preset), ctx.scene, plan.size(), dir.string());
  Progress progress(fmt::format("sweep {}", toString(preset)), std::uint64_t(std::ceil(totalCost)));
  std::vector<SweepRecord> records;
  const auto start = std::chrono::steady_clock::now();
  double doneCost = 0.0;
  std::size_t failed = 0;
  std::size_t finished = 0;
  for (std::size_t i = 0; i < plan.size() && !gStop; ++i) {
    std::vector<SweepRecord> rs;
    try {
      rs = runner.run(plan[i]);
    } catch (const SweepInterrupted&) {
      break;
    }
    for (const SweepRecord& r : rs) csv << csvRow(r) << "\n";
    csv << std::flush;
    if (!csv) throw Error(fmt::format("{}: write failed", csvPath.string()));
    const SweepRecord& r = rs.back();
    if (!r.ok()) ++failed;
    records.insert(records.end(), rs.begin(), rs.end());
    finished = i + 1;
    doneCost += plan[i].estimatedCost(s.repeats);
    progress.add(std::uint64_t(plan[i].estimatedCost(s.repeats)));
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double eta = elapsed * (totalCost - doneCost) / std::max(doneCost, 1e-9);
    if (r.ok() && r.point.group == SweepGroup::Storage)
      spdlog::info("[{}/{}] {}: {} active voxels, .vdb {:.2f} MiB vs dense {:.1f} MiB; ETA {}", i + 1, plan.size(),
                   r.point.label(), r.maskVoxels, r.vdbBytes / 1048576.0, r.denseBytes / 1048576.0, seconds(eta));
    else if (r.ok())
      spdlog::info("[{}/{}] {}: {:.1f} ms/frame, mean |error| {:.3f} voxels, peak {:.0f} MiB; ETA {}", i + 1,
                   plan.size(), r.point.label(), r.frameMs, r.meanAbs, r.peakMiB, seconds(eta));
    else
      spdlog::warn("[{}/{}] {}: could not run: {}; ETA {}", i + 1, plan.size(), r.point.label(), r.note, seconds(eta));
  }
  progress.finish();
  csv.close();
  // A Ctrl-C after the last point stopped nothing.
  ctx.interrupted = gStop.load() && finished < plan.size();
  if (ctx.interrupted) spdlog::warn("sweep interrupted: writing the report of the {} records finished", records.size());

  std::string plotError;
  try {
    ctx.plots = writeSweepPlots(dir, records, ctx.scene);
  } catch (const Error& e) {
    plotError = e.what();
  }
  writeTextAtomically(dir / "report.md", markdownReport(ctx, records));
  spdlog::info("wrote {}, {} and {} plot(s) in {}", csvPath.filename().string(), "report.md", ctx.plots.size(),
               dir.string());
  if (failed) spdlog::warn("{} point(s) could not run; report.md says why", failed);
  if (ctx.interrupted) {
    if (!plotError.empty()) spdlog::error("{}", plotError);
    return 130;
  }
  if (!plotError.empty()) throw Error(plotError);
  return 0;
}

} // namespace rtsdf::app
