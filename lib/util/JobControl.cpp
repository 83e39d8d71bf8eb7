#include "util/JobControl.h"

#include "util/Error.h"
#include "util/Progress.h"

#include <algorithm>
#include <vector>

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
  // A stack of bars: a stage that starts while another is unfinished (the anchor's bake inside a comparison,
  // the exact bake inside a stage) is drawn inside it and ends before the outer one reports again; a stage that
  // restarts (done goes back) starts a new bar.
  struct Bar {
    std::string stage;
    std::unique_ptr<Progress> progress;
    std::uint64_t done = 0;
  };
  auto bars = std::make_shared<std::vector<Bar>>();
  JobControl c;
  c.stopRequested = std::move(stop);
  c.progress = [bars](const std::string& stage, std::uint64_t done, std::uint64_t total) {
    auto at = std::find_if(bars->begin(), bars->end(), [&](const Bar& b) { return b.stage == stage; });
    // Bars inside this stage's end; on a restart (done goes back) this stage's own too.
    const auto end = at == bars->end() ? at : done < at->done ? at : at + 1;
    for (auto inner = bars->end(); inner != end;) (--inner)->progress->finish();
    bars->erase(end, bars->end());
    if (bars->empty() || bars->back().stage != stage)
      bars->push_back(Bar{stage, std::make_unique<Progress>(stage, total), 0});
    Bar& bar = bars->back();
    bar.progress->add(done - bar.done);
    bar.done = done;
    if (done >= total) {
      bar.progress->finish();
      bars->pop_back();
    }
  };
  return c;
}

} // namespace rtsdf
