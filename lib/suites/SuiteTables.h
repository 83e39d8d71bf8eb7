#pragma once
/// @file SuiteTables.h
/// @brief The Markdown tables of each suite of runBenchSuite (one source file per suite) and the timing they share;
///        runBenchSuite puts the machine line before them and writes the report.
#include "suites/Suites.h"
#include "util/JobControl.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief The median wall time in seconds of @a repeats runs of @a run (at least one).
template <typename F>
double medianSeconds(int repeats, F&& run) {
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

/// @brief The median GPU time of @a s.repeats runs of @a run (each returns its pass's milliseconds), after one run
///        that pays for pipelines and allocations and @a s.warmUpSeconds of runs for the GPU's clocks.
double warmMedianMs(const BenchOptions& s, const std::function<double()>& run);

/// @brief The coarse-SDF suite: GPU pass times per coarse method (the exact transform and the jump-flooding
///        variants) beside the CPU jump flooding, the CPU exact EDT of the same seeds and OpenVDB's full-domain
///        meshToSignedDistanceField, at the same voxels; each method's errors against the exact EDT.
std::string coarseSuite(const BenchOptions& s, const JobControl& control);

/// @brief The refinement suite: the paper's tables (ray-trace pass time for x at sizes S and M; band d x rays)
///        with the error against the exact field beside each time, and OpenVDB's meshToLevelSet at the fine
///        resolution and band as the anchor.
std::string refineSuite(const BenchOptions& s, const JobControl& control);

/// @brief The renderer suite: per-pass GPU times of SDF shadows and shadow maps at 640x360 and 1280x720 (median
///        over frames after warm-up), their image error against the ray-traced truth of the same frame, and the
///        ray tracer's time per sample count, to find the samples at which it reaches the SDF's error.
std::string renderSuite(const BenchOptions& s, const JobControl& control);

/// @brief The sign suite: every method (exact, OpenVDB, closest mode with x = 0 and 1, rays mode with x = 10) on
///        meshes whose faces lie (inside-out, 1/20/50% flipped, parts passing through each other, an inner shell)
///        and on open scans of several pieces, in units of 1 and of 1000: wrong signs and errors against the clean
///        solid, sign disagreement with OpenVDB, time and its ratio to OpenVDB's. At the first of the options'
///        resolutions (default 96 in the CLI's table); options.scenes, when given, picks the cases whose names
///        contain one of its entries ("open scan" runs the scans alone).
std::string signSuite(const BenchOptions& s, const JobControl& control);

/// @brief The reference suite: the exact SDF against OpenVDB's meshToLevelSet, same voxels and band.
std::string referenceSuite(const BenchOptions& s, const JobControl& control);

/// @brief The open-mesh case of the reference suite: the bunny split in four three times (235k triangles) with 12
///        small holes cut, the scan with holes users bring. Exact (the rim-only winding number) against OpenVDB at
///        the same voxels and band, a 3-voxel band and the suite's band fraction, and against the winding number
///        everywhere (the sign rule before rim-only), whose signs it must keep.
/// @note Each suite reports its points done to its control (JobPoll: "<suite> suite", points done of all) and
///       stops between points when it asks (Interrupted).
std::string openMeshCase(const BenchOptions& s, const JobControl& control);

} // namespace rtsdf::bench
