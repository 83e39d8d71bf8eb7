// rtsdf bench's suites: the builders against their anchors, same voxels and band, one run. Each suite's tables
// are in a file of their own (CoarseSuite.cpp, RefineSuite.cpp, RenderSuite.cpp, ReferenceSuite.cpp, SignSuite.cpp,
// FrameSuite.cpp).
#include "suites/Suites.h"

#include "suites/CascadeSuite.h"
#include "suites/FrameSuite.h"
#include "suites/SuiteTables.h"

#include "grid/GridSpec.h"
#include "jobs/JobSupport.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Settings.h"

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <functional>
#include <thread>

namespace rtsdf::bench {
namespace fs = std::filesystem;

std::string cpuName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string benchIgnores(const BenchOptions& o, bool sweep, const std::string& setting) {
  using S = BenchSuite;
  // Read by these suites (and the sweep where bySweep); who: them in words, for the message.
  const auto readBy = [&](std::initializer_list<S> suites, bool bySweep, const char* who) -> std::string {
    if (sweep) return bySweep ? "" : fmt::format("does not apply to the sweep (only {})", who);
    for (S s : suites)
      if (s == o.suite) return {};
    return fmt::format("does not apply to the {} suite (only {}): leave it out or choose that suite",
                       toString(o.suite), who);
  };
  for (const char* f : {"frame size", "frames", "refinement mode", "rays", "frame csv"})
    if (setting == f) return readBy({S::Frame, S::Cascade}, false, "the frame and cascade suites read it");
  for (const char* f : {"still", "full recompute", "full rebuild", "fine storage"})
    if (setting == f) return readBy({S::Frame}, false, "the frame suite reads it");
  if (setting == "cascades" || setting == "cascade extent" || setting == "cascade view margin" ||
      setting == "shade size")
    return readBy({S::Cascade}, false, "the cascade suite reads it");
  if (setting == "resolution")
    return readBy({S::Reference, S::Coarse, S::Sign}, false, "the reference, coarse and sign suites read it");
  if (setting == "band fraction") return readBy({S::Reference}, false, "the reference suite reads it");
  if (setting == "repeats")
    return readBy({S::Reference, S::Coarse, S::Refine}, true,
                  "the reference, coarse and refine suites and the sweep read it");
  if (setting == "warm-up seconds")
    return readBy({S::Coarse, S::Refine, S::Render, S::Frame, S::Cascade}, false,
                  "the coarse, refine, render, frame and cascade suites read it");
  if (setting == "device")
    return readBy({S::Coarse, S::Refine, S::Render, S::Frame, S::Sign, S::Cascade}, true,
                  "the GPU suites and the sweep read it");
  if (setting == EnumNames<BenchSuite>::kSetting) return sweep ? "does not apply to the sweep (it runs no suite)" : "";
  for (const char* f : {"output folder", "error band", "shadows", "truth samples"})
    if (setting == f) return sweep ? "" : "does not apply to a suite (only the sweep, --sweep, reads it)";
  return {};
}

double warmMedianMs(const BenchOptions& s, const std::function<double()>& run) {
  run();
  warmUpGpu(s.warmUpSeconds, run);
  std::vector<double> t;
  for (int r = 0; r < s.repeats; ++r) t.push_back(run());
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

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
  requireInRange("cascades", cascades, 1, kMaxCascades);
  if (cascadeExtent >= 0.0) requireInRange("cascade extent", cascadeExtent, 1e-9, 1e9);
  if (cascadeViewMargin >= 0.0) requireInRange("cascade view margin", cascadeViewMargin, 0.0, 1e6);
  if (shade != std::pair<int, int>{0, 0}) {
    requireInRange("shade size", shade.first, 1, 16384);
    requireInRange("shade size", shade.second, 1, 16384);
  }
  for (int r : resolutions) requireInRange("resolution", r, 1, GridSpec::kMaxResolution);
}

std::string runBenchSuite(const BenchOptions& options, const JobControl& control) {
  options.validate();
  BenchOptions s = options;
  if (s.scenes.empty()) s.scenes = {bundledScene("default.json"), bundledScene("bunny.json")};
  if (s.suite == BenchSuite::Frame) s.scenes.resize(1);
  if (s.suite == BenchSuite::Cascade && options.scenes.empty())
    throw SettingError("scenes", "the cascade suite needs scenes with a camera path (scripts/make_level.py --size 50, "
                                 "200 and 1000 writes the measured towns)");
  const std::vector<fs::path> inputs(s.scenes.begin(), s.scenes.end());
  if (!s.output.empty()) checkOutputPath(s.output, {}, inputs);
  if (!s.csv.empty()) checkOutputPath(s.csv, ".csv", inputs);
  std::string md = fmt::format("Machine: {}, {} hardware threads. Date: {:%Y-%m-%d}.\n\n", cpuName(),
                               std::thread::hardware_concurrency(), fmt::localtime(std::time(nullptr)));
  control.checkStop();
  switch (s.suite) {
  case BenchSuite::Coarse: md += coarseSuite(s, control); break;
  case BenchSuite::Refine: md += refineSuite(s, control); break;
  case BenchSuite::Render: md += renderSuite(s, control); break;
  case BenchSuite::Sign: {
    BenchOptions sign = s;
    sign.scenes = options.scenes; // names of its cases, not scenes
    md += signSuite(sign, control);
    break;
  }
  case BenchSuite::Cascade: {
    const CascadeRun run = runCascadeSuite(s, control);
    md += cascadeReport(s, run);
    if (!s.csv.empty()) writeTextAtomically(s.csv, cascadeCsv(run));
    break;
  }
  case BenchSuite::Frame: {
    const std::vector<FrameRow> rows = runFrames(s, control);
    md += frameReport(s, rows);
    if (!s.csv.empty()) writeTextAtomically(s.csv, frameCsv(rows));
    break;
  }
  case BenchSuite::Reference:
    md += referenceSuite(s, control);
    if (options.scenes.empty()) md += openMeshCase(s, control);
    break;
  }
  if (!s.output.empty()) writeTextAtomically(s.output, md);
  return md;
}

} // namespace rtsdf::bench
