#include "suites/FrameSuite.h"

#include "jobs/Animate.h"
#include "jobs/JobSupport.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <tuple>

namespace rtsdf::bench {

namespace {

double mib(std::uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

/// The median of @a get over frames 2..N (all frames when there is only one).
template <class Get> double medianAfterFirst(const std::vector<FrameRow>& rows, Get get) {
  std::vector<double> v;
  for (std::size_t i = rows.size() > 1 ? 1 : 0; i < rows.size(); ++i) v.push_back(get(rows[i]));
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The median GPU time of each pass over frames 2..N (0 in a frame that skipped it), and the frames that ran it.
std::string passMedians(const std::vector<FrameRow>& rows) {
  std::vector<std::string> passes;
  for (const FrameRow& r : rows)
    for (const auto& entry : r.passMs)
      if (std::find(passes.begin(), passes.end(), entry.first) == passes.end()) passes.push_back(entry.first);
  std::string md = "GPU time by pass, medians of frames 2..N (0 where a frame skipped the pass):\n\n| pass | GPU (ms) | "
                   "frames that ran it |\n|---|---|---|\n";
  for (const std::string& pass : passes) {
    std::size_t ran = 0;
    for (const FrameRow& r : rows)
      ran += std::any_of(r.passMs.begin(), r.passMs.end(), [&](const auto& e) { return e.first == pass; });
    md += fmt::format("| {} | {:.2f} | {} of {} |\n", pass,
                      medianAfterFirst(rows, [&](const FrameRow& r) { return passTotal(r.passMs, pass); }), ran,
                      rows.size());
  }
  return md + "\n";
}

} // namespace

std::string frameCsv(const std::vector<FrameRow>& rows) {
  std::string csv = "frame,host_ms,gpu_ms,wall_ms,mask_voxels,refined_voxels,mean_abs_error_voxels,wrong_sign_pct,"
                    "peak_mib,time,active_bricks,pool_bricks,overflow_bricks,device_mib,coarse_voxelized,"
                    "coarse_rebuilt,mask_visited,upsampled\n";
  for (const FrameRow& r : rows)
    csv += fmt::format("{},{:.4f},{:.4f},{:.4f},{},{},{:.6f},{:.6f},{:.1f},{:.6g},{},{},{},{:.1f},{},{},{},{}\n",
                       r.frame, r.hostMs, r.gpuMs, r.wallMs, r.maskVoxels, r.refinedVoxels, r.meanAbsErrorVoxels,
                       r.wrongSignPct, r.peakMiB, r.time, r.activeBricks, r.poolBricks, r.overflowBricks, r.deviceMiB,
                       r.voxelizedVoxels, r.rebuiltVoxels, r.maskVisitedVoxels, r.upsampledVoxels);
  return csv;
}

std::vector<FrameRow> runFrames(const BenchOptions& s, const JobControl& control) {
  AnimateOptions a;
  a.scene = s.scenes.empty() ? bundledScene("default.json") : s.scenes.front();
  a.frames = s.frames;
  a.still = s.still;
  a.device = s.device;
  a.pipeline = PipelineSettings{};
  std::tie(a.pipeline.coarseRes, a.pipeline.fineRes) = frameSizeResolutions(s.frameSize);
  a.pipeline.band = 0.1; // d = 0.1 scene units: the recorded frame figures' band (docs/results.md)
  a.pipeline.mode = s.refine;
  a.pipeline.rays = s.rays;
  a.pipeline.fullRecompute = s.fullRecompute;
  a.pipeline.fullRebuild = s.fullRebuild;
  a.pipeline.fineStorage = s.fineStorage;
  resetPeakResidentMemory();
  // With a warm-up, the frames are timed back to back as a game runs them, after the warm-up has raised the
  // GPU's clocks, and measured in a second run of the same frames: the host's exact field between frames would
  // leave the GPU idle long enough to slow it down (5.6x on an H100, measured). The pipeline is deterministic,
  // so both runs refine the same voxels.
  std::vector<FrameRow> timed;
  if (s.warmUpSeconds > 0.0) {
    AnimateOptions t = a;
    t.measureError = false;
    t.warmUpSeconds = s.warmUpSeconds;
    animate(t, control, [&](const AnimateFrame& f) {
      timed.push_back({});
      FrameRow& r = timed.back();
      r.hostMs = f.stats.hostMs;
      r.gpuMs = f.gpuMs();
      r.wallMs = f.stats.wallMs;
      r.refinedVoxels = f.stats.refinedFineVoxels;
      r.passMs = f.stats.passMs;
      spdlog::info("frame {} timed: host {:.2f} ms, GPU {:.1f} ms, wall {:.1f} ms", f.frame + 1, r.hostMs, r.gpuMs,
                   r.wallMs);
    });
  }
  std::vector<FrameRow> rows;
  animate(a, control, [&](const AnimateFrame& f) {
    FrameRow r;
    r.frame = f.frame + 1;
    r.time = f.time;
    r.hostMs = f.stats.hostMs;
    r.gpuMs = f.gpuMs();
    r.wallMs = f.stats.wallMs;
    r.maskVoxels = f.stats.maskFineVoxels;
    r.refinedVoxels = f.stats.refinedFineVoxels;
    r.activeBricks = f.stats.activeBricks;
    r.poolBricks = f.stats.poolBricks;
    r.overflowBricks = f.stats.overflowBricks;
    r.deviceMiB = mib(f.deviceBytesAllocated);
    r.voxelizedVoxels = f.stats.coarseVoxelizedVoxels;
    r.rebuiltVoxels = f.stats.coarseRebuiltVoxels;
    r.maskVisitedVoxels = f.stats.maskVisitedVoxels;
    r.upsampledVoxels = f.stats.upsampledFineVoxels;
    r.passMs = f.stats.passMs;
    r.meanAbsErrorVoxels = f.error.meanAbs;
    r.wrongSignPct = 100.0 * f.error.signErrorRate();
    r.peakMiB = mib(peakResidentMemory());
    if (!timed.empty()) {
      const FrameRow& t = timed[rows.size()];
      if (t.refinedVoxels != r.refinedVoxels)
        spdlog::warn("frame {}: the timed run refined {} voxels, the measured run {}", r.frame, t.refinedVoxels,
                     r.refinedVoxels);
      std::tie(r.hostMs, r.gpuMs, r.wallMs, r.passMs) = std::tuple(t.hostMs, t.gpuMs, t.wallMs, t.passMs);
    }
    spdlog::info("frame {}: host {:.2f} ms, GPU {:.1f} ms, wall {:.1f} ms, mask {}, error {:.4f} voxels", r.frame,
                 r.hostMs, r.gpuMs, r.wallMs, r.maskVoxels, r.meanAbsErrorVoxels);
    rows.push_back(r);
  });
  return rows;
}

std::string frameReport(const BenchOptions& s, const std::vector<FrameRow>& rows) {
  const auto [coarse, fine] = frameSizeResolutions(s.frameSize);
  std::string md = fmt::format("## Frames: {}, size {} (coarse {} / fine {}), {} refinement ({}), x = {}, d = 0.1, "
                               "alpha = 0.95, {}, fine storage {}\n\n",
                               s.scenes.empty() ? std::string("default.json") : s.scenes.front(), toString(s.frameSize),
                               coarse, fine, toString(s.refine), s.fullRecompute ? "full recompute"
                               : s.fullRebuild  ? "incremental refinement, every pass rebuilt"
                                                : "incremental",
                               s.rays,
                               s.still ? "static (every frame at time 0)" : "animated at 30 fps",
                               toString(s.fineStorage));
  md += s.warmUpSeconds > 0.0
            ? fmt::format("Medians of frames 2..N (the first frame allocates). Times: the frames run back to back after "
                          "{} s of warm-up frames; errors: a second run of the same frames, each measured against the "
                          "exact field:\n\n",
                          s.warmUpSeconds)
            : "Medians of frames 2..N (the first frame allocates and warms up):\n\n";
  md += "| host (ms) | GPU (ms) | wall (ms) | mask voxels | refined voxels | mean abs error (voxels) | wrong sign | "
        "peak MiB | device MiB | active bricks | pool bricks |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  md += fmt::format("| {:.3f} | {:.1f} | {:.1f} | {:.0f} | {:.0f} | {:.4f} | {:.4f}% | {:.0f} | {:.0f} | {:.0f} | {} "
                    "|\n\n",
                    medianAfterFirst(rows, [](const FrameRow& r) { return r.hostMs; }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return r.gpuMs; }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return r.wallMs; }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return double(r.maskVoxels); }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return double(r.refinedVoxels); }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return r.meanAbsErrorVoxels; }),
                    medianAfterFirst(rows, [](const FrameRow& r) { return r.wrongSignPct; }),
                    rows.empty() ? 0.0 : rows.back().peakMiB, rows.empty() ? 0.0 : rows.back().deviceMiB,
                    medianAfterFirst(rows, [](const FrameRow& r) { return double(r.activeBricks); }),
                    rows.empty() ? 0 : rows.back().poolBricks);
  md += passMedians(rows);
  md += "| frame | time (s) | host (ms) | GPU (ms) | wall (ms) | mask voxels | refined voxels | mean abs error "
        "(voxels) | wrong sign |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const FrameRow& r : rows)
    md += fmt::format("| {} | {:.3f} | {:.3f} | {:.1f} | {:.1f} | {} | {} | {:.4f} | {:.4f}% |\n", r.frame, r.time,
                      r.hostMs, r.gpuMs, r.wallMs, r.maskVoxels, r.refinedVoxels, r.meanAbsErrorVoxels,
                      r.wrongSignPct);
  return md + "\n";
}

} // namespace rtsdf::bench
