#include "util/Interrupt.h"

#include <array>
#include <climits>
#include <csignal>
#include <cstring>
#include <unistd.h>

namespace rtsdf {
namespace {

/// Registered temporary paths, claimed by an atomic flag so the handler never reads a half-written name.
struct TempSlot {
  std::atomic<int> state{0}; // 0 free, 1 being written, 2 registered
  char path[PATH_MAX] = {};
};
std::array<TempSlot, 16> gTemps;
std::atomic<std::atomic<bool>*> gGraceful{nullptr};

extern "C" void onTerminatingSignal(int sig) {
  if (std::atomic<bool>* stop = gGraceful.load(); stop && !stop->exchange(true)) return;
  for (TempSlot& s : gTemps)
    if (s.state.load() == 2) ::unlink(s.path);
  static const char kMessage[] = "[error] interrupted\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
  ::_exit(128 + sig);
}

} // namespace

void installInterruptHandlers() {
  struct sigaction sa = {};
  sa.sa_handler = onTerminatingSignal;
  sigemptyset(&sa.sa_mask);
  // Both signals blocked inside the handler: a second one cannot interrupt the clean-up half-way.
  sigaddset(&sa.sa_mask, SIGINT);
  sigaddset(&sa.sa_mask, SIGTERM);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // A file-size limit (ulimit -f) is a failed write, which the writers report with the file's name, not a crash
  // that leaves a temporary file behind.
  std::signal(SIGXFSZ, SIG_IGN);
}

GracefulStop::GracefulStop(std::atomic<bool>& stop) { gGraceful.store(&stop); }
GracefulStop::~GracefulStop() { gGraceful.store(nullptr); }

TemporaryFileGuard::TemporaryFileGuard(const std::filesystem::path& path) {
  const std::string s = path.string();
  if (s.size() >= PATH_MAX) return;
  for (int i = 0; i < int(gTemps.size()); ++i) {
    int expected = 0;
    if (!gTemps[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(gTemps[i].path, s.c_str(), s.size() + 1);
    gTemps[i].state.store(2);
    mSlot = i;
    return;
  }
}

TemporaryFileGuard::~TemporaryFileGuard() {
  if (mSlot >= 0) gTemps[mSlot].state.store(0);
}

} // namespace rtsdf
