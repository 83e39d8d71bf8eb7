#pragma once
/// @file Animate.h
/// @brief The RTSDF pipeline over an animation: per frame the ray mask, the GPU pass times, the host's CPU
///        time and the error against the exact field of the same moment (ghosting), optionally a .vdb per frame.
#include "grid/VdbIO.h"
#include "metrics/FieldError.h"
#include "scene/MeshIO.h"
#include "sdf/SdfPipeline.h"
#include "util/JobControl.h"
#include "util/Knobs.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief Everything an animation run needs.
struct AnimateOptions {
  std::string scene;          ///< scene (.json) or mesh file
  MeshLoadOptions meshLoad;   ///< whether the scene's mesh paths and meshes' references may leave their folder
  int frames = 60;
  double fps = 30.0;          ///< frames per second of scene time
  bool still = false;         ///< every frame at time 0: the scene held still (a static scene's frames)
  bool measureError = true;   ///< each frame against the exact field of the same moment
  std::string focus;          ///< measure only in the box this instance sweeps over the animation (ghosting)
  std::filesystem::path vdbDir; ///< write frameNNNN.vdb (the fine SDF's band) into this folder; empty: none
  VdbWriteOptions vdb;        ///< how the frameNNNN.vdb files are written (compression, up axis)
  std::string device;         ///< Vulkan device by index or name; empty: the best one
  /// Seconds of untimed full frames at time 0, on a pipeline of its own, before the first frame: a GPU's clocks
  /// rise only under sustained load (warmUpGpu). The frames measured are the same with or without it.
  double warmUpSeconds = 0.0;
  PipelineSettings pipeline = defaultPipeline();
  /// @brief The pipeline's own defaults (PipelineSettings), the same as every other job's.
  static PipelineSettings defaultPipeline();
  /// @throw SettingError naming the setting that is out of range (or a vdbDir that is not a folder).
  void validate() const;
};

/// @brief An animation run's own knobs (the pipeline's: KnobTable<PipelineSettings>); docs/settings.md.
template <> struct KnobTable<AnimateOptions> {
  using S = AnimateOptions;
  static constexpr auto kKnobs = std::make_tuple(
      knob("frames", &S::frames, "--frames", KnobRange::closed(1, 100000), "Frames to run"),
      knob("fps", &S::fps, "--fps", KnobRange::above(0), "Frames per second of scene time"),
      flagKnob("still", &S::still, "", "Every frame at time 0: the scene held still"),
      flagKnob("measure error", &S::measureError, "!--no-error",
               "Compare each frame with the exact field of the same moment; the flag skips it"),
      knob("focus", &S::focus, "--focus", KnobRange::any(),
           "Measure the error only in the box this instance sweeps (e.g. teapot: ghosting behind it)"),
      knob("vdb folder", &S::vdbDir, "--vdb-dir", KnobRange::any(),
           "Write frameNNNN.vdb files (fine SDF band) into this folder"),
      knob("device", &S::device, "--device", KnobRange::any(), "Vulkan device by index or name (see 'rtsdf info')"),
      knob("warm-up seconds", &S::warmUpSeconds, "", KnobRange::closed(0, 60),
           "Seconds of untimed full frames before the first, so that a GPU's clocks have risen"));
};

/// @brief One frame of an animation run.
struct AnimateFrame {
  int frame = 0;
  double time = 0.0;
  FrameStats stats;
  FieldError error;           ///< zero when not measured
  std::uint64_t deviceBytesAllocated = 0; ///< the device memory the pipeline holds after the frame, as allocated
                                          ///< (VulkanContext::deviceBytesInUse; stats.deviceBytes is the estimate)
  double gpuMs() const { return passSum(stats.passMs); }
};

/// @brief The whole run.
struct AnimateResult {
  GridSpec coarse, fine;
  std::vector<AnimateFrame> frames;
  /// @brief One CSV row per frame: frame, time, mask sizes, pass times, host time, error.
  std::string csv() const;
};

/// @brief @a pipe's fine field against the exact field of @a scene at @a t seconds, over the fine voxels in the band
///        (|exact| <= fineLevelSetBand), within @a focus (fine index space) when not null; a cascade level's voxels
///        out of the view's reach (SdfPipeline::outOfViewVoxels: the coarse SDF) are left out.
FieldError fieldErrorAgainstExact(const Scene& scene, const SdfPipeline& pipe, double t,
                                  const openvdb::CoordBBox* focus = nullptr);

/// @brief Run the pipeline over @a options.frames frames of @a options.scene.
/// @param onFrame called after each frame (e.g. to print it), may be empty.
/// @throw SettingError, Error as bake() does; Interrupted when @a control asks to stop between frames.
/// @note The frameNNNN.vdb files of options.vdbDir are removed again when the run throws.
AnimateResult animate(const AnimateOptions& options, const JobControl& control = {},
                      const std::function<void(const AnimateFrame&)>& onFrame = {});

} // namespace rtsdf
