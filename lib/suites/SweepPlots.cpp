#include "suites/SweepPlots.h"

#include "util/AtomicFile.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <sys/wait.h>

namespace rtsdf::bench {
namespace fs = std::filesystem;
namespace {

/// One named series of (x, y[, label]) rows, in a tab-separated file gnuplot reads.
struct Series {
  std::string file, title, style;
  std::string rows;
};

std::string clean(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '"') c = ' ';
  return s;
}

bool measured(const SweepRecord& r) { return r.ok() && std::isfinite(r.meanAbs) && std::isfinite(r.frameMs); }

std::string seriesName(const SweepRecord& r) {
  if (r.point.pipeline.mode == RefineMode::Closest) return "closest";
  return fmt::format("rays x={}", r.point.pipeline.rays);
}

std::string plotCommand(const std::vector<Series>& series, const std::string& using_) {
  std::string cmd = "plot ";
  bool first = true;
  for (const Series& s : series) {
    if (s.rows.empty()) continue;
    if (!first) cmd += ", \\\n     ";
    first = false;
    const bool labels = s.style.find("labels") != std::string::npos;
    cmd += fmt::format("'{}' using {} {} {}", s.file, labels ? "1:2:3" : using_, s.style,
                       s.title.empty() ? std::string("notitle") : fmt::format("title \"{}\"", s.title));
  }
  return first ? "" : cmd + "\n";
}

/// Series made on their first row, kept in that order (the plots' legends follow the sweep's order).
struct OrderedSeries {
  std::map<std::string, Series> byKey;
  std::vector<std::string> order;

  /// Appends @a row to the series of @a key; its first row makes it as make(n), n the series' 1-based number.
  template <class Make>
  void add(const std::string& key, const std::string& row, Make make) {
    if (!byKey.count(key)) {
      order.push_back(key);
      byKey[key] = make(order.size());
    }
    byKey[key].rows += row;
  }

  void appendTo(std::vector<Series>& all) const {
    for (const auto& k : order) all.push_back(byKey.at(k));
  }
};

/// The gnuplot script being written, the PNGs it makes, and the folder of the plots' data (the script's folder).
struct PlotScript {
  fs::path dataDir;
  std::string gp;
  std::vector<std::string> pngs;

  /// Writes the series' data files and, when any series has rows, a plot of them into @a png: the output, then
  /// @a settings (title, axes, key), then the plot command.
  void add(const std::vector<Series>& series, const std::string& png, const std::string& settings) {
    for (const Series& s : series)
      if (!s.rows.empty()) writeTextAtomically(dataDir / s.file, s.rows);
    if (const std::string cmd = plotCommand(series, "1:2"); !cmd.empty()) {
      gp += fmt::format("set output '../{}'\n{}{}", png, settings, cmd);
      pngs.push_back(png);
    }
  }
};

/// 1. Time vs error: every pipeline point by group, the front, brute force and anchors marked.
void addParetoPlot(PlotScript& script, const std::vector<SweepRecord>& rs, const std::string& title) {
  OrderedSeries byGroup;
  Series brute{"pareto_bruteforce.tsv", "brute force: d = inf (anchor)", "with points pt 9 ps 2.2 lc rgb '#d62728'",
               ""};
  Series vdb{"pareto_openvdb.tsv", "OpenVDB meshToLevelSet (anchor)", "with points pt 5 ps 2.2 lc rgb '#000000'", ""};
  Series exact{"pareto_exact.tsv", "exact reference (anchor)", "with points pt 13 ps 2.4 lc rgb '#2ca02c'", ""};
  Series front{"pareto_front.tsv", "Pareto front", "with lines lw 2 lc rgb '#888888'", ""};
  for (const SweepRecord& r : rs) {
    if (!measured(r)) continue;
    const std::string row = fmt::format("{:.6g}\t{:.6g}\t{}\n", r.frameMs, r.meanAbs, clean(r.point.label()));
    if (r.point.anchor == AnchorKind::OpenVdb) vdb.rows += row;
    else if (r.point.anchor == AnchorKind::Exact) exact.rows += row;
    else if (r.point.bruteForce) brute.rows += row;
    else if (r.point.group != SweepGroup::Dynamic) {
      const std::string g = toString(r.point.group);
      byGroup.add(g, row, [&](std::size_t) {
        return Series{fmt::format("pareto_{}.tsv", g), fmt::format("{} points", g), "with points pt 7 ps 1.3", ""};
      });
    }
  }
  for (std::size_t i : paretoFront(rs))
    front.rows += fmt::format("{:.6g}\t{:.6g}\t{}\n", rs[i].frameMs, rs[i].meanAbs, clean(rs[i].point.label()));
  // The front's points named beside them, so the plot says which settings to pick.
  Series frontLabels{front.file, "", "with labels left offset 0.6,0.5 font ',8' tc rgb '#444444'", front.rows};
  std::vector<Series> all{front, frontLabels};
  byGroup.appendTo(all);
  all.push_back(brute);
  all.push_back(vdb);
  all.push_back(exact);
  script.add(all, "pareto.png",
             fmt::format("set title \"{}: time vs accuracy (lower left is better; the front skips points with > 1% "
                         "wrong signs)\"\nset key outside right top\nset logscale x\nunset logscale y\nset xlabel "
                         "'time per frame (ms, log scale; anchors: CPU wall time)'\nset ylabel 'mean |error| (fine "
                         "voxels)'\n",
                         clean(title)));
}

/// 2. Time vs work: the frame time against the voxels refined, per refinement kind; anchors by their band.
void addWorkPlot(PlotScript& script, const std::vector<SweepRecord>& rs, const std::string& title) {
  OrderedSeries bySeries;
  Series vdb{"work_openvdb.tsv", "OpenVDB meshToLevelSet", "with linespoints pt 5 ps 1.8 lw 2 lc rgb '#000000'", ""};
  Series exact{"work_exact.tsv", "exact reference", "with linespoints pt 13 ps 1.8 lw 2 lc rgb '#2ca02c'", ""};
  for (const SweepRecord& r : rs) {
    if (!r.ok() || !std::isfinite(r.frameMs) || r.maskVoxels == 0) continue;
    const std::string row = fmt::format("{}\t{:.6g}\n", r.maskVoxels, r.frameMs);
    if (r.point.anchor == AnchorKind::OpenVdb) vdb.rows += row;
    else if (r.point.anchor == AnchorKind::Exact) exact.rows += row;
    else if (r.point.group == SweepGroup::Sizes || r.point.group == SweepGroup::Band) {
      const std::string k = seriesName(r);
      bySeries.add(k, row, [&](std::size_t n) {
        return Series{fmt::format("work_{}.tsv", n), k, "with points pt 7 ps 1.3", ""};
      });
    }
  }
  std::vector<Series> all;
  bySeries.appendTo(all);
  all.push_back(vdb);
  all.push_back(exact);
  script.add(all, "time_vs_work.png",
             fmt::format("set title \"{}: how cost grows with the work\"\nset logscale xy\nset xlabel 'fine voxels "
                         "refined (ray mask; anchors: voxels in their band), log'\nset ylabel 'time per frame (ms, "
                         "log)'\n",
                         clean(title)));
}

/// 3. Error vs frames: the static accumulation and each dynamic series, frame by frame.
void addFramesPlot(PlotScript& script, const std::vector<SweepRecord>& rs, const std::string& title) {
  Series stat{"frames_static.tsv", "static scene: error after N frames (x=1, alpha 0.95)", "with linespoints pt 7 lw 2",
              ""};
  OrderedSeries dyn;
  for (const SweepRecord& r : rs) {
    if (!measured(r)) continue;
    if (r.point.group == SweepGroup::Frames)
      stat.rows += fmt::format("{}\t{:.6g}\n", r.point.frames, r.meanAbs);
    else if (r.point.group == SweepGroup::Dynamic) {
      const std::string k = r.point.label();
      dyn.add(k, fmt::format("{}\t{:.6g}\n", r.frame + 1, r.meanAbs), [&](std::size_t n) {
        return Series{fmt::format("frames_dynamic_{}.tsv", n), "moving scene: " + clean(k),
                      "with linespoints pt 6 lw 2", ""};
      });
    }
  }
  std::vector<Series> all{stat};
  dyn.appendTo(all);
  script.add(all, "error_vs_frames.png",
             fmt::format("set title \"{}: error over frames\"\nset key inside top right opaque box\nunset logscale\n"
                         "set logscale x 2\nset xlabel 'frame (static: frames accumulated)'\nset ylabel 'mean |error| "
                         "vs the exact field of that frame (fine voxels)'\n",
                         clean(title)));
}

/// Writes the script and runs gnuplot on it in its folder; checks that every PNG it should write is there.
void runGnuplot(const fs::path& dir, const PlotScript& script) {
  const fs::path scriptFile = script.dataDir / "sweep.gp";
  writeTextAtomically(scriptFile, script.gp);
  for (const std::string& p : script.pngs) fs::remove(dir / p);
  // The folder in single quotes, any single quote in it closed, escaped and reopened.
  std::string quotedDir;
  for (char c : script.dataDir.string()) quotedDir += c == '\'' ? std::string("'\\''") : std::string(1, c);
  const std::string cmd = fmt::format("cd '{}' && gnuplot sweep.gp 2>&1", quotedDir);
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    const bool missing = WIFEXITED(rc) && WEXITSTATUS(rc) == 127;
    throw Error(fmt::format("{}: gnuplot {} (the plots' data and script are kept; install gnuplot-nox with "
                            "scripts/install-deps.sh and run `gnuplot sweep.gp` there)",
                            scriptFile.string(), missing ? "is not installed" : fmt::format("failed (status {})", rc)));
  }
  for (const std::string& p : script.pngs)
    if (!fs::exists(dir / p)) throw Error(fmt::format("{}: gnuplot wrote no {}", scriptFile.string(), p));
}

} // namespace

std::vector<std::string> writeSweepPlots(const fs::path& dir, const std::vector<SweepRecord>& rs,
                                         const std::string& title) {
  PlotScript script{dir / "plots",
                    "# gnuplot script written by the rtsdf sweep; rerun with: gnuplot sweep.gp (in this folder)\n"
                    "set terminal pngcairo size 1100,700 noenhanced font 'sans,11'\n"
                    "set datafile separator '\\t'\n"
                    "set grid\nset key outside right top\n",
                    {}};
  fs::create_directories(script.dataDir);
  addParetoPlot(script, rs, title);
  addWorkPlot(script, rs, title);
  addFramesPlot(script, rs, title);
  if (!script.pngs.empty()) runGnuplot(dir, script);
  return script.pngs;
}

} // namespace rtsdf::bench
