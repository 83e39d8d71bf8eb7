#pragma once
/// @file FrameSuite.h
/// @brief `rtsdf bench --suite frame`: the pipeline's frames one by one on one scene, each with its host, GPU and
///        wall time, its mask, and its error against the exact field of the same moment; one CSV row per frame.
#include "suites/Suites.h"
#include "sdf/SdfPipeline.h"

#include "util/PassTimes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief One row of the frame suite (frame numbers from 1: the first frame allocates and warms up).
struct FrameRow {
  int frame = 0;
  double time = 0.0;                 ///< scene time (s)
  double hostMs = 0.0;               ///< FrameStats::hostMs: CPU time outside the wait for the GPU
  double gpuMs = 0.0;                ///< the sum of the frame's pass timestamps
  double wallMs = 0.0;               ///< FrameStats::wallMs: runFrame from call to return
  std::uint64_t maskVoxels = 0;      ///< fine voxels in the ray mask
  std::uint64_t refinedVoxels = 0;   ///< fine voxels refined this frame
  double meanAbsErrorVoxels = 0.0;   ///< |fine - exact| over the band (|exact| <= fineLevelSetBand), fine voxels
  double wrongSignPct = 0.0;         ///< voxels of the band whose sign differs from the exact one, percent
  double peakMiB = 0.0;              ///< the process's peak resident memory since the suite began
  std::uint64_t activeBricks = 0;    ///< bricks of the sparse fine state under the band
  std::uint64_t poolBricks = 0;      ///< the brick pool's capacity
  std::uint64_t overflowBricks = 0;  ///< bricks under the band that found no slot (the next frame regrows the pool)
  double deviceMiB = 0.0;            ///< the device memory the pipeline holds, as allocated
                                     ///< (AnimateFrame::deviceBytesAllocated)
  /// Voxels each part touched (FrameStats): the coarse voxels voxelized, rebuilt (the distances written) and visited
  /// by the mask's compaction, and the dense fine voxels upsampled.
  std::uint64_t voxelizedVoxels = 0, rebuiltVoxels = 0, maskVisitedVoxels = 0, upsampledVoxels = 0;
  PassTimes passMs;                  ///< GPU time per pass (the passes a frame skipped are absent)
};

/// @brief The frame suite's CSV: the header `frame,host_ms,gpu_ms,wall_ms,mask_voxels,refined_voxels,
///        mean_abs_error_voxels,wrong_sign_pct,peak_mib,time,active_bricks,pool_bricks,overflow_bricks,device_mib,
///        coarse_voxelized,coarse_rebuilt,mask_visited,upsampled` and one line per row.
std::string frameCsv(const std::vector<FrameRow>& rows);

/// @brief Run the frame suite of @a options (options.scenes: one scene; options.frameSize, frames, refine,
///        still): one FrameRow per frame, in order.
/// @throw SettingError, Error as animate() does; Interrupted when @a control asks to stop between frames.
std::vector<FrameRow> runFrames(const BenchOptions& options, const JobControl& control = {});

/// @brief The Markdown report of @a rows: the settings, the medians of frames 2..N, and every frame.
std::string frameReport(const BenchOptions& options, const std::vector<FrameRow>& rows);

} // namespace rtsdf::bench
