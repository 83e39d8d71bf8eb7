#pragma once
/// @file Progress.h
/// @brief A thread-safe progress bar on stderr for long work (shown only when stderr is a terminal).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace rtsdf {

/// @brief Counts finished work items from any thread and redraws a bar at most ~10 times a second.
/// @note Silent when stderr is not a terminal or when progress is disabled globally (--quiet).
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
  bool mFinished = false;
};

} // namespace rtsdf
