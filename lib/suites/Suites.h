#pragma once
/// @file Suites.h
/// @brief The benchmark suites of `rtsdf bench`: each times rtsdf's builders against their anchors in one run
///        (OpenVDB's meshToLevelSet, the CPU references, the ray-traced truth) and reports Markdown tables.
#include "sdf/SdfPipeline.h"
#include "util/EnumNames.h"
#include "util/JobControl.h"

#include <filesystem>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief Which tables a benchmark run makes.
enum class BenchSuite {
  Reference, ///< exact SDF vs OpenVDB meshToLevelSet, same voxels and band
  Coarse,    ///< GPU voxelize + nearest-seed transform per pass and method vs CPU jump flooding, exact EDT, OpenVDB SDF
  Refine,    ///< the paper's ray-trace tables (sizes x rays, band x rays) with errors, vs OpenVDB meshToLevelSet
  Render,    ///< per-pass times of SDF shadows and shadow maps with their image error against the ray-traced truth;
             ///< the SDF shadows' pass times with the scene moving at 30 fps
  Frame,     ///< the pipeline frame by frame on one scene: host / GPU / wall time, mask, error (suites/FrameSuite.h)
  Sign,      ///< every method's signs on generated meshes whose faces lie, vs the clean solid and OpenVDB
  Cascade    ///< cascade levels along a camera path, walking and driving, vs every level rebuilt (CascadeSuite.h)
};

/// @brief The paper's three sizes of the frame suite.
enum class FrameSize {
  S, ///< coarse 64 / fine 128
  M, ///< coarse 128 / fine 256
  L  ///< coarse 256 / fine 512
};

/// @brief The coarse and fine resolutions of @a size.
std::pair<int, int> frameSizeResolutions(FrameSize size);

/// @brief Everything a benchmark run needs.
struct BenchOptions {
  /// Scenes or meshes; empty: the bundled default scene and the bunny, and for the reference suite also the
  /// open-mesh case (the bunny subdivided to 230k triangles with 12 holes cut).
  std::vector<std::string> scenes;
  std::vector<int> resolutions{128, 256}; ///< voxels across the longest side (reference and coarse suites)
  double bandFraction = 0.05;       ///< the band as a fraction of the scene's extent (reference suite)
  int repeats = 3;                  ///< timed runs per point; the median is reported
  BenchSuite suite = BenchSuite::Reference;
  std::string device;               ///< Vulkan device by index or name (GPU suites); empty: the best one
  /// Also write the report here (atomically); the render suite puts its PNGs beside it. Empty: neither.
  std::filesystem::path output;
  // The frame suite (one scene; default: the bundled default scene).
  FrameSize frameSize = FrameSize::M;
  int frames = 10;                        ///< frames run; the report's medians are over frames 2..N
  RefineMode refine = RefineMode::Closest;
  int rays = 1;                           ///< x (in closest mode: sign votes where the side is in doubt)
  bool fullRecompute = false;              ///< refine every masked voxel every frame (the paper's frame, the anchor)
  bool fullRebuild = false;                ///< run every pass of every frame over the whole grid (PipelineSettings)
  FineStorage fineStorage = FineStorage::Dense; ///< frame suite: a dense fine SDF resolved every frame, or bricks only
  bool still = false;                     ///< every frame at time 0 (static); default: the scene's animation at 30 fps
  std::filesystem::path csv;              ///< the frame and cascade suites' per-frame CSV (atomically); empty: none
  // The cascade suite (scenes with a camera path; also frameSize, frames, refine and rays).
  int cascades = 1;            ///< the levels (PipelineSettings::cascades); the suite needs 2 or more
  double cascadeExtent = -1.0; ///< level 0's side (PipelineSettings::cascadeExtent; < 0: the default rule)
  /// Levels above 0 refine within this many of their coarse voxels of the camera's view (the image at the --shade
  /// size, or render's default size; PipelineSettings::cascadeViewMargin; < 0: their whole band).
  double cascadeViewMargin = PipelineSettings{}.cascadeViewMargin;
  /// Also render each camera's incremental frames through the Renderer at this width and height (SDF shadows, the
  /// render command's defaults), timing the levels and the shading together: what a game's frame costs. {0, 0}: not.
  std::pair<int, int> shade{0, 0};
  /// Seconds of untimed GPU work before each timed run (GPU suites), on a pipeline or renderer of its own so
  /// that the measured one starts as it always does: a GPU's clocks rise only under sustained load (see
  /// warmUpGpu). 0: none, for tests and CPU devices.
  double warmUpSeconds = 1.0;
  /// @throw SettingError naming the setting that is out of range.
  void validate() const;
};

/// @brief Why `bench` with @a options (the speed/accuracy sweep instead when @a sweep) ignores the setting named
///        @a setting, as a clause after the flag ("does not apply to ..."), or "" when it reads it. The settings:
///        the frame suite's ("frame size", "frames", "refinement mode", "rays", "still", "full recompute",
///        "full rebuild", "fine storage", "frame csv"; of these the cascade suite reads "frame size", "frames",
///        "refinement mode", "rays" and "frame csv"), "cascades", "cascade extent", "cascade view margin" and
///        "shade size" (the cascade suite),
///        "resolution" (reference, coarse and sign suites), "band
///        fraction" (reference), "repeats" (reference, coarse, refine, the sweep), "warm-up seconds" (the GPU suites
///        that time frames: coarse, refine, render, frame, cascade), "device" (every GPU suite and the sweep), "benchmark
///        suite" (not the sweep), and the sweep's ("output folder", "error band", "shadows", "truth samples").
///        Others: "".
std::string benchIgnores(const BenchOptions& options, bool sweep, const std::string& setting);

/// @brief Run the suite of @a options and return its Markdown report (machine and date first).
/// @throw SettingError, Error (bad scenes, no Vulkan device for the GPU suites).
std::string runBenchSuite(const BenchOptions& options, const JobControl& control = {});

/// @brief The CPU's model name (from /proc/cpuinfo), for reports.
std::string cpuName();

} // namespace rtsdf::bench

namespace rtsdf {
template <> struct EnumNames<bench::BenchSuite> {
  static constexpr const char* kSetting = "benchmark suite";
  static constexpr std::pair<const char*, bench::BenchSuite> kValues[] = {{"reference", bench::BenchSuite::Reference},
                                                                          {"coarse", bench::BenchSuite::Coarse},
                                                                          {"refine", bench::BenchSuite::Refine},
                                                                          {"render", bench::BenchSuite::Render},
                                                                          {"frame", bench::BenchSuite::Frame},
                                                                          {"sign", bench::BenchSuite::Sign},
                                                                          {"cascade", bench::BenchSuite::Cascade}};
};
template <> struct EnumNames<bench::FrameSize> {
  static constexpr const char* kSetting = "frame size";
  static constexpr std::pair<const char*, bench::FrameSize> kValues[] = {
      {"S", bench::FrameSize::S}, {"M", bench::FrameSize::M}, {"L", bench::FrameSize::L}};
};
} // namespace rtsdf
