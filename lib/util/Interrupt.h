#pragma once
/// @file Interrupt.h
/// @brief SIGINT and SIGTERM at any moment: the temporary files of atomic writes in flight are removed, the
///        process says "interrupted" and exits with 128 + the signal (130, 143). A job that can stop cleanly
///        (the benchmark sweep) may instead ask for one graceful stop first.
#include <atomic>
#include <filesystem>

namespace rtsdf {

/// @brief Install the SIGINT/SIGTERM handlers of a command-line program, and ignore SIGXFSZ (a write past the
///        file-size limit then fails as a write error).
/// @note Handlers run async-signal-safe code only (unlink, write, _exit).
void installInterruptHandlers();

/// @brief While alive, the first SIGINT or SIGTERM sets @a stop instead of exiting; a second one exits.
///        Without installInterruptHandlers() this does nothing.
class GracefulStop {
public:
  explicit GracefulStop(std::atomic<bool>& stop);
  ~GracefulStop();
  GracefulStop(const GracefulStop&) = delete;
  GracefulStop& operator=(const GracefulStop&) = delete;
};

/// @brief A temporary file the interrupt handlers remove, registered for the scope of this object.
/// @note At most 16 at once; a 17th is written unregistered (and could then be left behind by a signal).
class TemporaryFileGuard {
public:
  explicit TemporaryFileGuard(const std::filesystem::path& path);
  ~TemporaryFileGuard();
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

private:
  int mSlot = -1;
};

} // namespace rtsdf
