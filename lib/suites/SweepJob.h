#pragma once
/// @file SweepJob.h
/// @brief `rtsdf bench --sweep` as one call: every point of a preset on one scene, CSV rows as points finish,
///        then the Markdown report and the plots in one folder. A stop request keeps what finished.
#include "suites/Sweep.h"
#include "suites/SweepRunner.h"
#include "util/JobControl.h"

#include <filesystem>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief Everything a sweep needs.
struct SweepJobOptions {
  std::string scene;                ///< scene or mesh; empty: the bundled default scene
  SweepPreset preset = SweepPreset::Default;
  std::filesystem::path outDir;     ///< created; empty: "sweep-" + the scene's name
  SweepRunOptions run;              ///< device, error band, repeats, shadows, truth samples (the quick preset
                                    ///< renders its shadow pictures at 160x90)
  std::string command;              ///< the command line that asked, for the report
  /// @throw SettingError / Error when a setting is out of range or the folder cannot be made.
  void validate() const;
};

/// @brief What a sweep did.
struct SweepJobResult {
  std::filesystem::path dir;        ///< where sweep.csv, report.md and the plots are
  std::vector<SweepRecord> records;
  std::size_t planned = 0, finished = 0, failed = 0;
  std::size_t plots = 0;
  bool interrupted = false;         ///< stopped before the last point (the report covers what finished)
  std::string plotError;            ///< why the plots could not be drawn (empty when they were)
};

/// @brief Run the sweep. Progress (with an ETA per point in the log) goes to @a control; its stop request ends
///        the sweep after the current frame and the report covers the finished points.
/// @throw SettingError, Error (bad scene, no Vulkan device, unwritable folder).
SweepJobResult runSweep(const SweepJobOptions& options, const JobControl& control = {});

} // namespace rtsdf::bench
