#pragma once
/// @file CascadeSuite.h
/// @brief `rtsdf bench --suite cascade`: camera-centred cascade levels (CascadeSet) following each scene's camera path,
///        once at walking and once at driving speed, frame by frame, and the same frames with every pass of every level
///        rebuilt each frame (the anchor), in one run: wall and GPU time (by pass), levels moved, voxels refined,
///        device memory, and at each run's last frame every level's error against the exact field.
#include "suites/Suites.h"
#include "util/PassTimes.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief One frame of one run of the cascade suite.
struct CascadeRow {
  std::string scene;  ///< the scene file as given
  std::string camera; ///< "walking" or "driving"
  std::string build;  ///< "incremental" or "full rebuild" (every pass of every level over its whole grid)
  int frame = 0;                   ///< from 1 (the first frame builds every level)
  double time = 0.0;               ///< scene time (s)
  double speed = 0.0;              ///< the camera's speed (scene units per second)
  int levelsMoved = 0;             ///< levels whose snapped box moved this frame (scrolled or rebuilt)
  int levelsRecut = 0;             ///< of those, the levels that scrolled with their scene cut again
  int levelsRebuilt = 0;           ///< of those, the levels rebuilt from scratch (CascadeMove::rebuilt)
  double moveMs = 0.0;             ///< CascadeSet::moveTo: the scrolls' shifts, the rebuilt levels' host work
  double gpuMs = 0.0;              ///< the sum of the frame's pass timestamps over every level
  double wallMs = 0.0;             ///< moveTo and runFrame, call to return
  std::uint64_t refinedVoxels = 0; ///< fine voxels refined this frame, every level
  std::uint64_t keptVoxels = 0;    ///< of those, listed for a moving instance and kept unwalked (movedKeptVoxels)
  /// Voxels each part touched this frame, every level (FrameStats): the coarse voxels voxelized, rebuilt (the
  /// distances written) and visited by the mask's compaction, and the fine voxels upsampled.
  std::uint64_t voxelizedVoxels = 0, rebuiltVoxels = 0, maskVisitedVoxels = 0, upsampledVoxels = 0;
  double deviceMiB = 0.0;          ///< the device memory every level holds, as allocated (VulkanContext::deviceBytesInUse)
  PassTimes passMs;                ///< GPU time per pass, every level's
};

/// @brief One level's fine field at a run's last frame against the exact field of that moment.
struct CascadeLevelError {
  std::string scene, camera;
  int level = 0;
  double voxelSize = 0.0;
  double meanAbsVoxels = 0.0, maxAbsVoxels = 0.0, wrongSignPct = 0.0;
};

struct CascadeRun {
  std::vector<CascadeRow> rows;
  std::vector<CascadeLevelError> errors;
  std::vector<std::string> notes; ///< what the run could not do (a path too slow to drive)
};

/// @brief Run the cascade suite of @a options (options.scenes: scenes with a camera path, e.g. scripts/make_level.py's
///        towns; cascades >= 2, cascadeExtent, frameSize, frames per run, refine, rays).
/// @throw SettingError naming "cascades" below 2 and "scenes" for a scene without a camera path; Error as
///        CascadeSet; Interrupted when @a control asks to stop between frames.
CascadeRun runCascadeSuite(const BenchOptions& options, const JobControl& control = {});

/// @brief The Markdown report: per scene and camera speed the medians of frames 2..N of both builds and their
///        ratio, the passes, and the levels' errors.
std::string cascadeReport(const BenchOptions& options, const CascadeRun& run);

/// @brief One CSV line per frame: `scene,camera,build,frame,time,speed,levels_moved,move_ms,gpu_ms,wall_ms,
///        refined_voxels,device_mib,kept_voxels,coarse_voxelized,coarse_rebuilt,mask_visited,upsampled`.
std::string cascadeCsv(const CascadeRun& run);

} // namespace rtsdf::bench
