#pragma once
/// @file JobControl.h
/// @brief What a caller passes into a long job (bake, animate, render, bench): where progress goes and how to
///        ask it to stop. Jobs report progress per stage and poll for a stop between units of work (frames,
///        benchmark points), like OpenVDB's interrupter.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace rtsdf {

class Progress;

/// @brief Progress sink and stop request of a job. A default-constructed control reports nothing and never
///        stops.
struct JobControl {
  /// Called with the finished and total work items of a stage (e.g. "refining", 3, 16); done == total ends
  /// the stage. Parallel jobs call it one report at a time, maybe from a worker thread (JobPoll).
  std::function<void(const std::string& stage, std::uint64_t done, std::uint64_t total)> progress;
  /// Polled between units of work; true stops the job (it throws Interrupted, or returns what finished where
  /// its contract says so). Parallel jobs poll it from their worker threads at once: it must be thread-safe.
  std::function<bool()> stopRequested;

  void report(const std::string& stage, std::uint64_t done, std::uint64_t total) const {
    if (progress) progress(stage, done, total);
  }
  bool stopping() const { return stopRequested && stopRequested(); }
  /// @throw Interrupted when a stop was requested.
  void checkStop() const;
};

/// @brief A parallel loop's view of a JobControl: stop requests polled from any worker thread (once one is seen,
///        every later poll says stop without asking again), and progress reported at about every 1% of the items,
///        one report at a time and never going back, whichever thread finished which item.
class JobPoll {
public:
  /// @param control the caller's control, or null (nothing reported, never stops).
  JobPoll(const JobControl* control, std::string stage, std::uint64_t total);
  JobPoll(const JobPoll&) = delete;
  JobPoll& operator=(const JobPoll&) = delete;
  /// @brief Whether the job should stop (thread-safe; asks control->stopRequested unless a stop was seen).
  bool stopping();
  /// @brief @a n more items finished (thread-safe).
  void done(std::uint64_t n = 1);

private:
  const JobControl* mControl;
  std::string mStage;
  std::uint64_t mTotal;
  std::atomic<std::uint64_t> mDone{0};
  std::atomic<bool> mStop{false};
  std::mutex mReportMutex;
  std::uint64_t mReported = 0;
};

/// @brief A control that reports each stage on stderr (util/Progress.h: a bar on a terminal, otherwise a line
///        every few seconds and one when the stage ends; nothing when progress is disabled) and stops when @a stop
///        returns true. A stage reported while another is unfinished is drawn inside it (a bake inside a
///        comparison).
JobControl terminalJobControl(std::function<bool()> stop = {});

} // namespace rtsdf
