#include "sdf/pipeline/FrameRecorder.h"

#include "sdf/refine/RefinePasses.h"
#include "util/Error.h"

namespace rtsdf {

double FrameStats::refineMs() const {
  return passTotal(RayRefinePass::kName) + passTotal(ClosestRefinePass::kName) + passTotal(WindingExactPass::kName);
}

FrameRecorder::FrameRecorder(const gpu::VulkanContext& ctx) : mProfiler(ctx), mCmd(ctx) {}

FrameRecorder::~FrameRecorder() {
  // A failed wait has nowhere to go.
  try {
    mCmd.wait();
  } catch (const std::exception&) {
  }
}

void FrameRecorder::wait() { mCmd.wait(); }

VkCommandBuffer FrameRecorder::begin() {
  mCmd.restart();
  const VkCommandBuffer cmd = mCmd.handle();
  mProfiler.reset(cmd);
  gpu::computeBarrier(cmd); // the previous frame's passes are done with what this one overwrites
  return cmd;
}

void FrameRecorder::submit(const FrameStats& stats, Clock::time_point hostStart) {
  mSubmitted = stats;
  mCmd.submit();
  mSubmitStart = hostStart;
  mSubmitted.hostMs = std::chrono::duration<double, std::milli>(Clock::now() - hostStart).count();
  mAwaitingFinish = true;
}

FrameStats FrameRecorder::finish(const std::function<void(FrameStats&)>& complete) {
  if (!mAwaitingFinish) throw Error("SdfPipeline: finishFrame() without a submitted frame");
  mAwaitingFinish = false;
  mCmd.wait();
  const auto t0 = Clock::now();
  FrameStats stats = mSubmitted;
  stats.passMs = mProfiler.results();
  complete(stats);
  const auto t1 = Clock::now();
  stats.hostMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
  stats.wallMs = std::chrono::duration<double, std::milli>(t1 - mSubmitStart).count();
  return stats;
}

} // namespace rtsdf
