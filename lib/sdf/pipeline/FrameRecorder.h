#pragma once
/// @file FrameRecorder.h
/// @brief The recording of a pipeline's frames: one command buffer reused frame after frame, its GPU profiler, and
///        the timing and statistics of the frame in flight (FrameRecorder).
#include "gpu/Profiler.h"
#include "gpu/Resources.h"
#include "sdf/pipeline/FrameStats.h"

#include <chrono>
#include <functional>

namespace rtsdf {

/// @brief One frame in flight at a time. Owns the frame's command buffer (restarted per frame: its pool's memory is
///        reused), the profiler its passes report to, the submitted frame's statistics so far and when its host work
///        began. Waits for the frame in flight when destroyed (the buffers the frame uses must outlive it: destroy
///        this part before them, or wait()).
class FrameRecorder {
public:
  using Clock = std::chrono::steady_clock;
  explicit FrameRecorder(const gpu::VulkanContext& ctx);
  ~FrameRecorder();
  FrameRecorder(const FrameRecorder&) = delete;
  FrameRecorder& operator=(const FrameRecorder&) = delete;

  /// @brief Wait for the frame in flight (no-op when none is).
  /// @throw VulkanError as CommandBuffer::wait does.
  void wait();
  /// @brief Begin recording a frame: waits for the previous one, resets the profiler, and records a barrier after
  ///        the previous frame's passes. Returns the command buffer.
  VkCommandBuffer begin();
  gpu::GpuProfiler* profiler() { return &mProfiler; }
  /// @brief Submit the recorded frame with its statistics @a stats so far; its host time runs from @a hostStart
  ///        to the return of the submission.
  void submit(const FrameStats& stats, Clock::time_point hostStart);
  /// @brief Whether a frame was submitted and finish() has not read it.
  bool awaitingFinish() const { return mAwaitingFinish; }
  /// @brief Wait for the submitted frame and return its statistics with the pass times; @a complete adds what the
  ///        pipeline reads back (its time counts as host time). Sets hostMs and wallMs.
  /// @throw Error when no frame was submitted since the last finish().
  FrameStats finish(const std::function<void(FrameStats&)>& complete);

private:
  gpu::GpuProfiler mProfiler;
  gpu::CommandBuffer mCmd;
  FrameStats mSubmitted;        ///< the submitted frame's statistics so far (host time of its recording)
  bool mAwaitingFinish = false; ///< a frame was submitted and finish() has not read it
  Clock::time_point mSubmitStart;
};

} // namespace rtsdf
