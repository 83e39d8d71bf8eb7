#include "util/JobControl.h"

#include "util/Error.h"
#include "util/Progress.h"

#include <algorithm>

namespace rtsdf {

void JobControl::checkStop() const {
  if (stopping()) throw Interrupted();
}

JobPoll::JobPoll(const JobControl* control, std::string stage, std::uint64_t total)
    : mControl(control), mStage(std::move(stage)), mTotal(total) {}

bool JobPoll::stopping() {
  if (mStop.load(std::memory_order_relaxed)) return true;
  if (!mControl || !mControl->stopping()) return false;
  mStop = true;
  return true;
}

void JobPoll::done(std::uint64_t n) {
  if (!mControl || !mControl->progress || mTotal == 0) return;
  const std::uint64_t now = mDone += n;
  // About 100 reports a stage: only the item that crosses a percent reports.
  if (now * 100 / mTotal == (now - n) * 100 / mTotal && now < mTotal) return;
  const std::lock_guard<std::mutex> lock(mReportMutex);
  const std::uint64_t latest = std::max(mDone.load(), mReported);
  if (latest == mReported) return;
  mReported = latest;
  mControl->report(mStage, std::min(latest, mTotal), mTotal);
}

JobControl terminalJobControl(std::function<bool()> stop) {
  // One bar at a time: a new stage (or a restart of the same one) finishes the previous bar.
  struct Bars {
    std::unique_ptr<Progress> bar;
    std::string stage;
    std::uint64_t done = 0;
  };
  auto bars = std::make_shared<Bars>();
  JobControl c;
  c.stopRequested = std::move(stop);
  c.progress = [bars](const std::string& stage, std::uint64_t done, std::uint64_t total) {
    if (!bars->bar || bars->stage != stage || done < bars->done) {
      if (bars->bar) bars->bar->finish();
      bars->bar = std::make_unique<Progress>(stage, total);
      bars->stage = stage;
      bars->done = 0;
    }
    bars->bar->add(done - bars->done);
    bars->done = done;
    if (done >= total) {
      bars->bar->finish();
      bars->bar.reset();
    }
  };
  return c;
}

} // namespace rtsdf
