// rtsdf: real-time signed distance fields of triangle-mesh scenes. The command line binds flags onto the
// library's options structs, calls one library job per subcommand and prints what it returns.
#include "suites/Suites.h"
#include "suites/SweepJob.h"
#include "jobs/Animate.h"
#include "jobs/Bake.h"
#include "jobs/Compare.h"
#include "jobs/MeshJob.h"
#include "jobs/RenderJob.h"
#include "jobs/SystemInfo.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Interrupt.h"
#include "util/Log.h"
#include "util/Progress.h"

#include "Options.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <exception>

namespace rtsdf::app {
namespace {

int runBake(const BakeCommand& c) {
  checkOutputPath(c.output, ".vdb", {c.options.scene});
  const BakeResult r = bake(c.options, terminalJobControl());
  writeBake(r, c.output, c.written);
  fmt::print("{}", bakeReport(c.options, r, c.output, c.written));
  return 0;
}

int runCompare(CompareCommand c) {
  if (c.againstFlag->count()) c.options.against = c.anchor;
  fmt::print("{}", compare(c.options, terminalJobControl()).report());
  return 0;
}

int runMesh(const MeshOptions& o) {
  fmt::print("{}", meshLevelSet(o, terminalJobControl()).report(o));
  return 0;
}

int runAnimate(const AnimateCommand& c) {
  if (!c.csv.empty()) checkOutputPath(c.csv, ".csv", {c.options.scene});
  const AnimateResult r = animate(c.options, terminalJobControl(), [](const AnimateFrame& f) {
    if (f.frame == 0)
      fmt::print("{:>5} {:>7} {:>10} {:>10} {:>10} {:>10} {:>10} {:>12} {:>12} {:>10}\n", "frame", "time", "mask",
                 "refined", "GPU ms", "host ms", "band", "mean err", "max err", "wrong sign");
    fmt::print("{:>5} {:>7.3f} {:>10} {:>10} {:>10.1f} {:>10.1f} {:>10} {:>12.4f} {:>12.3f} {:>9.3f}%\n", f.frame,
               f.time, f.stats.maskFineVoxels, f.stats.refinedFineVoxels, f.gpuMs(), f.stats.hostMs, f.error.voxels,
               f.error.meanAbs, f.error.maxAbs, 100.0 * f.error.signErrorRate());
  });
  if (!c.csv.empty()) writeTextAtomically(c.csv, r.csv());
  return 0;
}

int runRender(const RenderCommand& c) {
  const RenderOutputs out = RenderOutputs::forExr(c.output, c.png);
  out.check({c.options.scene});
  const RenderJobResult r = renderScene(c.options, terminalJobControl());
  const RenderSettings& rs = c.options.render;
  fmt::print("{} shadows, {}x{}, frame at t = {} s:\n{}", toString(rs.technique), rs.width, rs.height, c.options.time,
             r.passTable());
  if (r.compared)
    fmt::print("against ray-traced truth: visibility RMSE {:.4f}, mean |diff| {:.4f} ({} lit pixels); penumbra RMSE "
               "{:.4f} ({} pixels); umbra mean |diff| {:.4f} ({} pixels); FLIP {:.4f}\n",
               r.error.visibilityRmse, r.error.visibilityMeanAbs, r.error.pixels, r.error.penumbraRmse,
               r.error.penumbraPixels, r.error.umbraMeanAbs, r.error.umbraPixels, r.error.flip);
  writeRender(r, out);
  if (r.compared) fmt::print("wrote the visibility error picture {}\n", out.errorPng.string());
  fmt::print("wrote {} (channels {}) and {}\n", out.exr.string(), fmt::join(r.image.channelNames(), ", "),
             out.png.string());
  return 0;
}

int runView(const ViewOptions& o) {
  const ViewResult r = runViewer(o, terminalJobControl());
  fmt::print("{} frame(s), {:.1f} ms per frame\n{}\n", r.frames, r.meanFrameMs, r.lastLine);
  if (!o.screenshot.empty() && r.frames > 0) fmt::print("wrote {}\n", o.screenshot);
  return 0;
}

/// What `rtsdf bench` alone runs, and for how long, before it starts.
void announceBench(const bench::BenchOptions& s) {
  fmt::print(stderr, "rtsdf bench with no arguments runs the {} suite (the exact SDF against OpenVDB's "
                     "meshToLevelSet, timed) on the default scene, the bunny and a 230k-triangle scan with holes at "
                     "{} voxels, the median of {} timed runs per point. This takes several minutes on a 2-core CPU; "
                     "Ctrl-C stops it. 'rtsdf bench --help' lists the suites (--suite) and what they measure.\n",
             toString(s.suite), fmt::join(s.resolutions, " and "), s.repeats);
}

int runBench(const BenchCommand& c) {
  if (c.announce) announceBench(c.suite);
  if (c.sweep.empty()) {
    fmt::print("{}", bench::runBenchSuite(c.suite, terminalJobControl()));
    return 0;
  }
  // The first Ctrl-C stops the sweep after the current frame (the report then covers the finished points); a
  // second one ends it at once.
  std::atomic<bool> stop{false};
  const GracefulStop graceful(stop);
  bench::SweepJobOptions o = c.sweepOptions;
  o.preset = parseEnum<bench::SweepPreset>(c.sweep);
  if (c.suite.scenes.size() > 1) throw Error("the sweep runs on one scene (give one scene or mesh)");
  if (!c.suite.scenes.empty()) o.scene = c.suite.scenes.front();
  const bench::SweepJobResult r = bench::runSweep(o, terminalJobControl([&stop] { return stop.load(); }));
  if (r.interrupted) {
    if (!r.plotError.empty()) spdlog::error("{}", r.plotError);
    return 130;
  }
  if (!r.plotError.empty()) throw Error(r.plotError);
  return 0;
}

/// The message for a first word that names no subcommand ("frob"), or empty. CLI11 alone would say only that
/// a subcommand is required.
std::string unknownCommand(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue; // the global options are flags: no values to skip
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      if (sub->check_name(word)) return {};
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    return fmt::format("unknown command '{}' (commands: {})", word, names);
  }
  return {};
}

int run(const Commands& c) {
  if (c.which == "bake") return runBake(c.bake);
  if (c.which == "animate") return runAnimate(c.animate);
  if (c.which == "render") return runRender(c.render);
  if (c.which == "view") return runView(c.view);
  if (c.which == "bench") return runBench(c.bench);
  if (c.which == "compare") return runCompare(c.compare);
  if (c.which == "mesh") return runMesh(c.mesh);
  if (c.which == "help-settings") {
    fmt::print("{}", helpSettings());
    return 0;
  }
  const SystemInfo info = systemInfo();
  fmt::print("{}", info.text);
  return info.vulkanOk ? 0 : 1;
}

} // namespace
} // namespace rtsdf::app

int main(int argc, char** argv) {
  using namespace rtsdf::app;
  Commands commands;
  CLI::App app{"rtsdf: signed distance fields of triangle-mesh scenes (OpenVDB export, GPU coarse SDF and ray "
               "refinement, soft shadows)"};
  int verbosity = 0;
  bool quiet = false;
  bindCommands(app, commands, verbosity, quiet);
  if (const std::string unknown = unknownCommand(app, argc, argv); !unknown.empty()) {
    fmt::print(stderr, "{}\nRun with --help for more information.\n", unknown);
    return 1;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  commands.which = app.get_subcommands().front()->get_name();
  commands.bench.announce = argc == 2 && commands.which == "bench";
  std::string& command = commands.bench.sweepOptions.command; // for the sweep's report
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(i ? argv[i] : "rtsdf");
  rtsdf::installInterruptHandlers();
  rtsdf::initLogging(quiet ? -1 : verbosity);
  rtsdf::Progress::setEnabled(!quiet);
  try {
    finishCommands(app, commands);
    return run(commands);
  } catch (const rtsdf::Interrupted&) {
    spdlog::error("interrupted");
    return 130;
  } catch (const rtsdf::SettingError& e) {
    spdlog::error("{}: {}", commands.flags.flagOf(e.setting()), e.what());
  } catch (const rtsdf::Error& e) {
    spdlog::error("{}", e.what());
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory (try a lower --res or a narrower --band)");
  } catch (const std::exception& e) {
    spdlog::error("unexpected failure: {}", e.what());
  }
  return 1;
}
