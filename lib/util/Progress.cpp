#include "util/Progress.h"

#include <cstdio>
#include <unistd.h>

namespace rtsdf {
namespace {
std::atomic<bool> gEnabled{true};
}

void Progress::setEnabled(bool enabled) { gEnabled = enabled; }

Progress::Progress(std::string label, std::uint64_t total)
    : mLabel(std::move(label)), mTotal(total), mStart(std::chrono::steady_clock::now()) {
  mActive = gEnabled && total > 0;
  mTerminal = isatty(STDERR_FILENO);
}

Progress::~Progress() { finish(); }

void Progress::add(std::uint64_t n) {
  const std::uint64_t done = mDone.fetch_add(n, std::memory_order_relaxed) + n;
  if (!mActive) return;
  const auto now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                       std::chrono::steady_clock::now() - mStart).count();
  std::int64_t next = mNextDrawNs.load(std::memory_order_relaxed);
  if (now < next && done < mTotal) return;
  // A bar is redrawn ten times a second; a line is printed every five seconds, the last one by finish().
  if (!mTerminal && done >= mTotal) return;
  const std::int64_t period = mTerminal ? 100'000'000 : 5'000'000'000;
  if (!mNextDrawNs.compare_exchange_strong(next, now + period)) return; // another thread draws
  if (!mTerminal && next == 0) return; // the first item: the first line waits a period
  draw(false);
}

void Progress::finish() {
  if (!mActive || mFinished) return;
  mFinished = true;
  draw(true);
}

void Progress::draw(bool final) {
  std::lock_guard<std::mutex> lock(mDrawMutex);
  const std::uint64_t done = std::min(mDone.load(), mTotal);
  const double frac = mTotal ? double(done) / double(mTotal) : 1.0;
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
  constexpr int kWidth = 30;
  const int filled = int(frac * kWidth + 0.5);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double eta = frac > 0.0 ? secs * (1.0 - frac) / frac : 0.0;
  if (!mTerminal) {
    if (final) std::fprintf(stderr, "%s %llu/%llu done in %.1f s\n", mLabel.c_str(), (unsigned long long)done,
                            (unsigned long long)mTotal, secs);
    else std::fprintf(stderr, "%s %llu/%llu (%.0f%%), %.1f s so far, about %.0f s left\n", mLabel.c_str(),
                      (unsigned long long)done, (unsigned long long)mTotal, 100.0 * frac, secs, eta);
    std::fflush(stderr);
    return;
  }
  std::fprintf(stderr, "\r%-24s [%s] %5.1f%%  %.1fs elapsed, ETA %.1fs   ", mLabel.c_str(), bar,
               100.0 * frac, secs, eta);
  if (final) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

} // namespace rtsdf
