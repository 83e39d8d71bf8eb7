#pragma once
/// @file JobControl.h
/// @brief What a caller passes into a long job (bake, animate, render, bench): where progress goes and how to
///        ask it to stop. Jobs report progress per stage and poll for a stop between units of work (frames,
///        benchmark points), like OpenVDB's interrupter.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace rtsdf {

class Progress;

/// @brief Progress sink and stop request of a job. A default-constructed control reports nothing and never
///        stops.
struct JobControl {
  /// Called with the finished and total work items of a stage (e.g. "refining", 3, 16); done == total ends
  /// the stage.
  std::function<void(const std::string& stage, std::uint64_t done, std::uint64_t total)> progress;
  /// Polled between units of work; true stops the job (it throws Interrupted, or returns what finished where
  /// its contract says so).
  std::function<bool()> stopRequested;

  void report(const std::string& stage, std::uint64_t done, std::uint64_t total) const {
    if (progress) progress(stage, done, total);
  }
  bool stopping() const { return stopRequested && stopRequested(); }
  /// @throw Interrupted when a stop was requested.
  void checkStop() const;
};

/// @brief A control that draws each stage as a progress bar on stderr (util/Progress.h: only on a terminal,
///        and not when progress is disabled) and stops when @a stop returns true.
JobControl terminalJobControl(std::function<bool()> stop = {});

} // namespace rtsdf
