#include "util/JobControl.h"

#include "util/Error.h"
#include "util/Progress.h"

namespace rtsdf {

void JobControl::checkStop() const {
  if (stopping()) throw Interrupted();
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
