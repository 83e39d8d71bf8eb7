#pragma once
/// @file Sweep.h
/// @brief The speed/accuracy sweep behind `rtsdf bench --sweep`: which points a preset runs (the plan), what
///        one point measured (a record), the CSV rows, the Pareto front, and the Markdown report.
#include "sdf/SdfPipeline.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief How much a sweep covers.
enum class SweepPreset {
  Quick,   ///< tiny grids (32/64), a few points per knob: a smoke run of every table (about a minute on a CPU)
  Default, ///< sizes S and M, every knob at size S: the trade on a CPU Vulkan driver in minutes
  Paper    ///< the paper's tables: sizes S, M and L, band x rays at size M, every knob at M (for a real GPU)
};

/// @brief What a point varies: the table it belongs to in the report.
enum class SweepGroup {
  Sizes,   ///< grid sizes x rays per voxel (and closest-point mode)
  Band,    ///< band d x rays; d = inf is the brute-force anchor (every voxel refined)
  Alpha,   ///< history decay
  Frames,  ///< frames accumulated on a static scene
  Jfa,     ///< coarse method: the exact transform and the jump-flooding variants
  Dynamic, ///< the scene's animation: one record per frame, each against the exact field of that moment
  Anchor,  ///< OpenVDB meshToLevelSet and the exact reference at the same fine voxels and band
  Storage  ///< the band as a sparse .vdb file vs a dense grid, per fine resolution (exact field)
};

/// @brief The anchors measured beside the pipeline.
enum class AnchorKind { None, OpenVdb, Exact };

} // namespace rtsdf::bench

namespace rtsdf {
template <> struct EnumNames<bench::SweepPreset> {
  static constexpr const char* kSetting = "sweep preset";
  static constexpr std::pair<const char*, bench::SweepPreset> kValues[] = {{"quick", bench::SweepPreset::Quick},
                                                                           {"default", bench::SweepPreset::Default},
                                                                           {"paper", bench::SweepPreset::Paper}};
};
template <> struct EnumNames<bench::SweepGroup> {
  static constexpr const char* kSetting = "sweep group";
  static constexpr std::pair<const char*, bench::SweepGroup> kValues[] = {
      {"sizes", bench::SweepGroup::Sizes},     {"band", bench::SweepGroup::Band},
      {"alpha", bench::SweepGroup::Alpha},     {"frames", bench::SweepGroup::Frames},
      {"jfa", bench::SweepGroup::Jfa},         {"dynamic", bench::SweepGroup::Dynamic},
      {"anchor", bench::SweepGroup::Anchor},   {"storage", bench::SweepGroup::Storage}};
};
/// The anchors' names as the report prints them ("" for none).
template <> struct EnumNames<bench::AnchorKind> {
  static constexpr const char* kSetting = "anchor";
  static constexpr std::pair<const char*, bench::AnchorKind> kValues[] = {
      {"", bench::AnchorKind::None}, {"OpenVDB meshToLevelSet", bench::AnchorKind::OpenVdb},
      {"exact reference", bench::AnchorKind::Exact}};
};
} // namespace rtsdf

namespace rtsdf::bench {

/// @brief One point of a sweep.
struct SweepPoint {
  SweepGroup group = SweepGroup::Sizes;
  std::string size;            ///< "XS", "S", "M" or "L" (coarse/fine resolutions)
  /// The point's settings; d in scene units (the sweep's tables give d as the paper does, 0.1 for its 2-unit
  /// scenes), not the pipeline's default in voxels.
  PipelineSettings pipeline = [] {
    PipelineSettings s;
    s.band = 0.1;
    return s;
  }();
  int frames = 2;              ///< frames run; the error is taken after the last (every frame for Dynamic)
  AnchorKind anchor = AnchorKind::None;
  bool bruteForce = false;     ///< d = inf: the band covers the whole grid
  double storageBandVoxels = 0;///< Storage: the band's half-width in fine voxels; 0: the error band (scene units)
  /// @brief A short name for tables and logs, e.g. "S rays x=5 d=0.1".
  std::string label() const;
  /// @brief A rough relative cost (voxels x rays x frames), for the progress bar's ETA.
  /// @param repeats timed frames at least after the first (SweepRunOptions::repeats).
  double estimatedCost(int repeats = 3) const;
};

/// @brief The d used for "d = inf": far beyond any scene of the sweep (lengths are in scene units).
/// @param sceneExtent the scene's largest extent.
double bruteForceBand(double sceneExtent);

/// @brief The points a preset runs, in order: sizes, anchors, band, alpha, frames, JFA, dynamic, storage.
/// @param animated plan the Dynamic group (only scenes that move have one).
/// @param sceneExtent the scene's largest extent (for the brute-force band).
std::vector<SweepPoint> makeSweepPlan(SweepPreset preset, bool animated, double sceneExtent);

constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

/// @brief What one point (or one frame of a Dynamic point) measured.
struct SweepRecord {
  SweepPoint point;
  int frame = 0;               ///< the frame the error belongs to (0-based)
  double time = 0.0;           ///< scene time of that frame (s)
  std::uint64_t maskVoxels = 0;///< fine voxels in the ray mask
  double voxelizeMs = kNotMeasured, transformMs = kNotMeasured, distanceMs = kNotMeasured,
         upsampleMs = kNotMeasured, refineMs = kNotMeasured; ///< GPU pass times (pipeline points only)
  double hostMs = kNotMeasured;   ///< CPU time of the frame outside its wait for the GPU (FrameStats::hostMs)
  double frameMs = kNotMeasured;  ///< per-frame cost: the GPU passes plus the host time (anchors, storage: CPU wall time)
  double meanAbs = kNotMeasured, rms = kNotMeasured, maxAbs = kNotMeasured; ///< |error| in fine voxels
  double signErrorRate = kNotMeasured;
  std::uint64_t errorVoxels = 0;
  double shadowRmse = kNotMeasured, shadowPenumbraRmse = kNotMeasured, shadowFlip = kNotMeasured;
  double voxelSize = 0.0;      ///< the fine voxel h (scene units): the unit of the errors
  std::string grid;            ///< the fine grid's dimensions, e.g. "128x126x99"
  std::uint64_t vdbBytes = 0, denseBytes = 0; ///< Storage: the .vdb file and a dense float grid of the same box
  double peakMiB = kNotMeasured; ///< peak resident memory of the process while the point ran
  double peakGrowthMiB = kNotMeasured; ///< that peak minus the resident memory when the point started
  std::string note;            ///< why a point could not run (empty when it did)
  bool ok() const { return note.empty(); }
};

/// @brief The CSV header line (no newline) and one record as a CSV line (no newline). Unmeasured values
///        are empty fields; text fields are quoted.
std::string csvHeader();
std::string csvRow(const SweepRecord& r);

/// @brief Wrong-sign rate above which a point cannot be on the Pareto front: its field has holes (an SDF with
///        wrong signs lets shadows leak or casts them from nothing), however small its mean error.
constexpr double kParetoMaxSignErrorRate = 0.01;

/// @brief Indices of the records on the Pareto front of (frameMs, meanAbs): no other eligible record is both
///        faster and more accurate. Eligible: static pipeline records that ran and were measured over at least
///        one voxel (no anchors, no Dynamic series: a moving scene is another trade), with at most
///        @a maxSignErrorRate wrong signs. Sorted by time.
std::vector<std::size_t> paretoFront(const std::vector<SweepRecord>& records,
                                     double maxSignErrorRate = kParetoMaxSignErrorRate);

/// @brief Facts for the report's header.
struct SweepContext {
  std::string scene, command, machine, device, date;
  SweepPreset preset = SweepPreset::Default;
  double errorBand = 0.1;      ///< where the field error is measured: |exact| <= errorBand (scene units)
  int shadowWidth = 0, shadowHeight = 0, truthSamples = 0; ///< 0: the scene has no camera, no shadow error
  std::size_t planned = 0;     ///< points planned (records may be fewer after an interrupt)
  int repeats = 3;             ///< timed frames at least, after the warm-up frame
  bool interrupted = false;
  std::vector<std::string> plots; ///< PNG file names beside the report
};

/// @brief The Markdown report: the paper's tables (pass durations; sizes x rays; band d x rays), the other
///        knobs, the anchors with ratios, the Pareto front, and every point with its peak memory.
std::string markdownReport(const SweepContext& ctx, const std::vector<SweepRecord>& records);

} // namespace rtsdf::bench
