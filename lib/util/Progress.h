#pragma once
/// @file Progress.h
/// @brief A thread-safe progress report on stderr for long work: a bar on a terminal, lines elsewhere (a pipe, a
///        log file).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace rtsdf {

/// @brief Counts finished work items from any thread. On a terminal it redraws a bar at most ~10 times a second;
///        when stderr is not a terminal it prints a line (what it does, how far, the time left) every few seconds
///        and one when the stage ends.
/// @note Silent when progress is disabled globally (--quiet).
class Progress {
public:
  Progress(std::string label, std::uint64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// @brief Record @a n more finished items (thread-safe, cheap).
  void add(std::uint64_t n = 1);
  /// @brief Draw the final state and end the line.
  void finish();

  /// @brief Enable or disable all progress output (e.g. from --quiet or tests).
  static void setEnabled(bool enabled);

private:
  void draw(bool final);
  std::string mLabel;
  std::uint64_t mTotal;
  std::atomic<std::uint64_t> mDone{0};
  std::atomic<std::int64_t> mNextDrawNs{0};
  std::chrono::steady_clock::time_point mStart;
  std::mutex mDrawMutex;
  bool mActive = false;
  bool mTerminal = false; ///< a bar redrawn in place; else a line at a time
  bool mFinished = false;
};

} // namespace rtsdf
