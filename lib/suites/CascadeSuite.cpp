#include "suites/CascadeSuite.h"

#include "jobs/Animate.h"
#include "jobs/JobSupport.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/cascade/CascadeSet.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <numeric>

namespace rtsdf::bench {

namespace {

constexpr double kFps = 30.0;
/// A camera faster than this (scene units per second) drives: scripts/make_level.py's towns walk at 1.4 m/s and
/// drive at 12.
constexpr double kDrivingSpeed = 4.0;

double speedAt(const Scene& scene, double t) {
  return glm::length(scene.cameraAt(t + 1.0 / kFps).position - scene.cameraAt(t).position) * kFps;
}

/// When the camera path first drives (-1: never), scanned frame by frame.
double drivingStart(const Scene& scene) {
  const double end = scene.cameraPath.back().time;
  for (double t = 0.0; t < end; t += 1.0 / kFps)
    if (speedAt(scene, t) > kDrivingSpeed) return t;
  return -1.0;
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The median of @a get over frames 2..N of @a rows (all of them when there is one).
/// The values of frames 2..N (all of them when there is one).
template <class Get> std::vector<double> afterFirst(const std::vector<const CascadeRow*>& rows, Get get) {
  std::vector<double> v;
  for (std::size_t i = rows.size() > 1 ? 1 : 0; i < rows.size(); ++i) v.push_back(get(*rows[i]));
  return v;
}

template <class Get> double medianAfterFirst(const std::vector<const CascadeRow*>& rows, Get get) {
  std::vector<double> v = afterFirst(rows, get);
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The mean of frames 2..N: a level moves in some frames only, so the median can miss what moving costs.
template <class Get> double meanAfterFirst(const std::vector<const CascadeRow*>& rows, Get get) {
  const std::vector<double> v = afterFirst(rows, get);
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

template <class Get> double maxAfterFirst(const std::vector<const CascadeRow*>& rows, Get get) {
  const std::vector<double> v = afterFirst(rows, get);
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

struct RunSpec {
  std::string sceneName, camera, build;
  double start = 0.0;
  bool fullRebuild = false;
};

/// Frame @a f (from 0) of @a spec's run, its moment and the camera's speed filled in.
CascadeRow frameRow(const Scene& scene, const RunSpec& spec, int f) {
  CascadeRow r;
  r.scene = spec.sceneName;
  r.camera = spec.camera;
  r.build = spec.build;
  r.frame = f + 1;
  r.time = spec.start + f / kFps;
  r.speed = speedAt(scene, r.time);
  return r;
}

void countMoves(const CascadeMove& move, CascadeRow& r) {
  r.levelsMoved = int(move.moved.size());
  r.levelsRecut = int(move.recut.size());
  r.levelsRebuilt = int(move.rebuilt.size());
}

/// The frame's counts of @a stats (every level's, summed) into @a r.
void countVoxels(const FrameStats& stats, CascadeRow& r) {
  r.refinedVoxels = stats.refinedFineVoxels;
  r.keptVoxels = stats.movedKeptVoxels;
  r.voxelizedVoxels = stats.coarseVoxelizedVoxels;
  r.rebuiltVoxels = stats.coarseRebuiltVoxels;
  r.maskVisitedVoxels = stats.maskVisitedVoxels;
  r.upsampledVoxels = stats.upsampledFineVoxels;
}

/// One run: the levels built around the camera at spec.start, then options.frames frames at 30 fps.
/// The image's width over height the levels' view reach assumes: the shaded size, else the render command's default.
double viewAspect(const BenchOptions& o) {
  const RenderSettings r;
  return o.shade.first > 0 ? double(o.shade.first) / o.shade.second : double(r.width) / r.height;
}

void runOne(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds, PipelineSettings ps,
            const BenchOptions& o, const RunSpec& spec, const JobControl& control, JobPoll& progress,
            CascadeRun& out) {
  ps.fullRebuild = ps.fullRecompute = spec.fullRebuild;
  const Camera eye = scene.cameraAt(spec.start);
  const CascadeShape shape = cascadeShapeFor(bounds, eye.position, ps);
  const CascadeLayout layout = CascadeLayout::around(eye.position, shape, cascadeLookAhead(eye, shape.levelZeroExtent));
  if (o.warmUpSeconds > 0.0) { // the GPU's clocks, on levels of their own: the measured ones start as they always do
    PipelineSettings full = ps;
    full.fullRebuild = full.fullRecompute = true;
    CascadeSet warm(ctx, scene, layout, full);
    warmUpGpu(o.warmUpSeconds, [&] { warm.runFrame(spec.start); });
  }
  CascadeSet set(ctx, scene, layout, ps);
  const double aspect = viewAspect(o);
  for (int f = 0; f < o.frames; ++f) {
    control.checkStop();
    CascadeRow r = frameRow(scene, spec, f);
    const auto t0 = std::chrono::steady_clock::now();
    const Camera at = scene.cameraAt(r.time);
    countMoves(set.moveTo(at.position, cascadeLookAhead(at, shape.levelZeroExtent)), r);
    set.setView(at, aspect); // as the renderer does before each frame
    r.moveMs = msSince(t0);
    const FrameStats stats = sumFrameStats(set.runFrame(r.time));
    r.wallMs = msSince(t0);
    r.gpuMs = passSum(stats.passMs);
    countVoxels(stats, r);
    r.deviceMiB = double(ctx.deviceBytesInUse()) / (1024.0 * 1024.0); // what the levels hold: the set alone is on ctx
    r.passMs = stats.passMs;
    spdlog::info("{} {} {}: frame {}, {} level(s) moved ({} rebuilt), wall {:.1f} ms, GPU {:.1f} ms", r.scene,
                 r.camera, r.build, r.frame, r.levelsMoved, r.levelsRebuilt, r.wallMs, r.gpuMs);
    out.rows.push_back(std::move(r));
    progress.done();
  }
  if (spec.fullRebuild) return;
  const double t = out.rows.back().time;
  for (int i = 0; i < set.levels(); ++i) {
    control.checkStop();
    const FieldError e = fieldErrorAgainstExact(set.levelScene(i), set.level(i), t);
    out.errors.push_back({spec.sceneName, spec.camera, i, set.level(i).fineSpec().voxelSize, e.meanAbs, e.maxAbs,
                          100.0 * e.signErrorRate()});
  }
}

std::string shadedBuild(const BenchOptions& o) { return fmt::format("shaded {}x{}", o.shade.first, o.shade.second); }

/// The incremental frames of @a spec through the Renderer at o.shade (SDF shadows, the render command's defaults, no
/// read-back): the levels' passes and the shading's, one GPU frame as a game would run it.
void runShaded(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& bounds, const PipelineSettings& ps,
               const BenchOptions& o, const RunSpec& spec, const JobControl& control, JobPoll& progress,
               CascadeRun& out) {
  RenderSettings rs;
  rs.width = o.shade.first;
  rs.height = o.shade.second;
  rs.pipeline = ps;
  if (o.warmUpSeconds > 0.0) { // on a renderer of its own: the measured one's levels and TAA history start fresh
    Renderer warm(ctx, scene, bounds, rs, spec.start);
    warmUpGpu(o.warmUpSeconds, [&] { warm.renderFrame(spec.start, false); });
  }
  Renderer renderer(ctx, scene, bounds, rs, spec.start);
  for (int f = 0; f < o.frames; ++f) {
    control.checkStop();
    CascadeRow r = frameRow(scene, spec, f);
    const auto t0 = std::chrono::steady_clock::now();
    const RenderedFrame frame = renderer.renderFrame(r.time, false);
    r.wallMs = msSince(t0);
    countMoves(frame.cascadeMove, r);
    r.gpuMs = passSum(frame.passMs);
    countVoxels(frame.sdf, r);
    r.deviceMiB = double(ctx.deviceBytesInUse()) / (1024.0 * 1024.0);
    r.passMs = frame.passMs;
    spdlog::info("{} {} {}: frame {}, {} level(s) moved, wall {:.1f} ms, GPU {:.2f} ms", r.scene, r.camera, r.build,
                 r.frame, r.levelsMoved, r.wallMs, r.gpuMs);
    out.rows.push_back(std::move(r));
    progress.done();
  }
}

} // namespace

CascadeRun runCascadeSuite(const BenchOptions& o, const JobControl& control) {
  if (o.cascades < 2)
    throw SettingError("cascades", fmt::format("the cascade suite needs 2 or more levels, not {}", o.cascades));
  PipelineSettings ps;
  std::tie(ps.coarseRes, ps.fineRes) = frameSizeResolutions(o.frameSize);
  ps.mode = o.refine;
  ps.rays = o.rays;
  ps.cascades = o.cascades;
  ps.cascadeExtent = o.cascadeExtent;
  ps.cascadeViewMargin = o.cascadeViewMargin;
  ps.fineStorage = FineStorage::Dense; // as the renderer's levels, and the error's read-back
  CascadeRun run;
  // Frames of every run: two camera speeds and two builds (three when shaded) per scene; a path that never drives
  // skips a speed.
  const bool shaded = o.shade != std::pair<int, int>{0, 0};
  const std::uint64_t builds = shaded ? 3 : 2;
  JobPoll progress(&control, "cascade suite", std::uint64_t(o.scenes.size()) * 2 * builds * std::uint64_t(o.frames));
  for (const std::string& path : o.scenes) {
    const Scene scene = loadScene(path);
    const std::string& name = path; // as given: towns from make_level.py share the file name level.json
    if (scene.cameraPath.empty())
      throw SettingError("scenes", fmt::format("{}: the cascade suite follows the scene's camera path, and this scene "
                                               "has none (scripts/make_level.py writes towns with one)",
                                               path));
    const Bounds bounds = buildSceneGeometry(scene, 0.0).bounds;
    std::vector<std::pair<std::string, double>> cameras{{"walking", 0.0}};
    const double drive = drivingStart(scene);
    if (drive >= 0.0) cameras.emplace_back("driving", drive);
    else {
      run.notes.push_back(fmt::format("{}: the camera path never moves faster than {} units/s: no driving run", name,
                                      kDrivingSpeed));
      progress.done(builds * std::uint64_t(o.frames));
    }
    runOnDevice(deviceContextOptions(o.device), [&](const gpu::VulkanContext& ctx) {
      for (const auto& [camera, start] : cameras) {
        for (const bool full : {false, true})
          runOne(ctx, scene, bounds, ps, o, {name, camera, full ? "full rebuild" : "incremental", start, full}, control,
                 progress, run);
        if (shaded)
          runShaded(ctx, scene, bounds, ps, o, {name, camera, shadedBuild(o), start, false}, control, progress, run);
      }
      return 0;
    });
  }
  return run;
}

std::string cascadeCsv(const CascadeRun& run) {
  std::string csv = "scene,camera,build,frame,time,speed,levels_moved,levels_recut,levels_rebuilt,move_ms,gpu_ms,"
                    "wall_ms,refined_voxels,device_mib,kept_voxels,coarse_voxelized,coarse_rebuilt,mask_visited,"
                    "upsampled\n";
  for (const CascadeRow& r : run.rows)
    csv += fmt::format("{},{},{},{},{:.4f},{:.3f},{},{},{},{:.3f},{:.3f},{:.3f},{},{:.1f},{},{},{},{},{}\n", r.scene,
                       r.camera, r.build, r.frame, r.time, r.speed, r.levelsMoved, r.levelsRecut, r.levelsRebuilt,
                       r.moveMs, r.gpuMs, r.wallMs, r.refinedVoxels, r.deviceMiB, r.keptVoxels, r.voxelizedVoxels,
                       r.rebuiltVoxels, r.maskVisitedVoxels, r.upsampledVoxels);
  return csv;
}

namespace {

/// The rows of one scene, camera and build, in frame order.
std::vector<const CascadeRow*> select(const CascadeRun& run, const std::string& scene, const std::string& camera,
                                      const std::string& build) {
  std::vector<const CascadeRow*> rows;
  for (const CascadeRow& r : run.rows)
    if (r.scene == scene && r.camera == camera && r.build == build) rows.push_back(&r);
  return rows;
}

/// One build's row of the scene table: medians of frames 2..N (and the GPU time's mean and largest).
struct BuildSummary {
  double wall = 0.0, gpu = 0.0, gpuMean = 0.0;
  std::string row;
};

BuildSummary summarize(const CascadeRun& run, const std::string& scene, const std::string& camera,
                       const std::string& build) {
  const std::vector<const CascadeRow*> rows = select(run, scene, camera, build);
  const auto gpuOf = [](const CascadeRow& r) { return r.gpuMs; };
  BuildSummary b;
  b.wall = medianAfterFirst(rows, [](const CascadeRow& r) { return r.wallMs; });
  b.gpu = medianAfterFirst(rows, gpuOf);
  b.gpuMean = meanAfterFirst(rows, gpuOf);
  // The renderer moves its levels inside its frame: a shaded frame's moveTo is part of its wall time.
  const bool shaded = build != "incremental" && build != "full rebuild";
  const double moveMedian = medianAfterFirst(rows, [](const CascadeRow& r) { return r.moveMs; });
  const std::string moveMs = shaded ? "(in wall)" : fmt::format("{:.1f}", moveMedian);
  b.row = fmt::format("| {} | {} | {:.1f} | {:.2f} | {:.2f} | {:.2f} | {} | {:.2f} / {:.2f} / {:.2f} | "
                      "{:.0f} / {:.0f} | {:.1f} |\n",
                      camera, build, b.wall, b.gpu, b.gpuMean, maxAfterFirst(rows, gpuOf), moveMs,
                      meanAfterFirst(rows, [](const CascadeRow& r) { return double(r.levelsMoved); }),
                      meanAfterFirst(rows, [](const CascadeRow& r) { return double(r.levelsRecut); }),
                      meanAfterFirst(rows, [](const CascadeRow& r) { return double(r.levelsRebuilt); }),
                      medianAfterFirst(rows, [](const CascadeRow& r) { return double(r.refinedVoxels); }),
                      medianAfterFirst(rows, [](const CascadeRow& r) { return double(r.keptVoxels); }),
                      rows.empty() ? 0.0 : rows.back()->deviceMiB);
  return b;
}

/// A table of means of frames 2..N, one column per camera and build: a row per (name, value of a frame), each mean
/// printed with @a decimals.
using FrameValue = std::function<double(const CascadeRow&)>;
std::string meansTable(const CascadeRun& run, const std::string& scene, const std::vector<std::string>& cameras,
                       const std::vector<std::string>& builds, const std::string& corner,
                       const std::vector<std::pair<std::string, FrameValue>>& rows, int decimals) {
  std::string md = "| " + corner + " |", rule = "|---|";
  for (const std::string& camera : cameras)
    for (const std::string& build : builds) {
      md += fmt::format(" {} {} |", camera, build);
      rule += "---|";
    }
  md += "\n" + rule + "\n";
  for (const auto& [name, value] : rows) {
    md += "| " + name + " |";
    for (const std::string& camera : cameras)
      for (const std::string& build : builds)
        md += fmt::format(" {:.{}f} |", meanAfterFirst(select(run, scene, camera, build), value), decimals);
    md += "\n";
  }
  return md;
}

/// The voxels each part touched, every level, means of frames 2..N.
std::string touchedTable(const CascadeRun& run, const std::string& scene, const std::vector<std::string>& cameras,
                         const std::vector<std::string>& builds) {
  const auto count = [](std::uint64_t CascadeRow::*field) {
    return FrameValue([field](const CascadeRow& r) { return double(r.*field); });
  };
  return "\nVoxels each part touched, every level, means of frames 2..N:\n\n" +
         meansTable(run, scene, cameras, builds, "voxels",
                    {{"coarse voxels voxelized (VoxelizePass)", count(&CascadeRow::voxelizedVoxels)},
                     {"coarse voxels rebuilt (ExactEdtPass's z lines, CoarseDistancePass)",
                      count(&CascadeRow::rebuiltVoxels)},
                     {"coarse voxels the mask visited (MaskCompactPass)", count(&CascadeRow::maskVisitedVoxels)},
                     {"fine voxels upsampled (UpsamplePass)", count(&CascadeRow::upsampledVoxels)},
                     {"fine voxels refined", count(&CascadeRow::refinedVoxels)}},
                    0);
}

std::string sceneReport(const CascadeRun& run, const std::string& scene) {
  std::vector<std::string> cameras, builds, passes;
  const auto addOnce = [](std::vector<std::string>& v, const std::string& s) {
    if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
  };
  for (const CascadeRow& r : run.rows) {
    if (r.scene != scene) continue;
    addOnce(cameras, r.camera);
    addOnce(builds, r.build);
    for (const auto& entry : r.passMs) addOnce(passes, entry.first);
  }
  std::string md = fmt::format("### {}\n\n| camera | build | wall (ms) | GPU (ms) | GPU mean (ms) | GPU max (ms) | "
                               "moveTo (ms) | levels moved / recut / rebuilt per frame | refined voxels / of them "
                               "kept | device MiB |\n|---|---|---|---|---|---|---|---|---|---|\n",
                               scene);
  for (const std::string& camera : cameras) {
    const BuildSummary inc = summarize(run, scene, camera, "incremental");
    const BuildSummary full = summarize(run, scene, camera, "full rebuild");
    md += inc.row + full.row;
    md += fmt::format("| {} | incremental / full rebuild | {:.3f} | {:.3f} | {:.3f} | | | | | |\n", camera,
                      full.wall > 0.0 ? inc.wall / full.wall : 0.0, full.gpu > 0.0 ? inc.gpu / full.gpu : 0.0,
                      full.gpuMean > 0.0 ? inc.gpuMean / full.gpuMean : 0.0);
    for (const std::string& build : builds) // the shaded frames: the levels and the shading, one GPU frame
      if (build != "incremental" && build != "full rebuild") md += summarize(run, scene, camera, build).row;
  }
  std::vector<std::pair<std::string, FrameValue>> passRows;
  for (const std::string& pass : passes)
    passRows.emplace_back(pass, [pass](const CascadeRow& r) { return passTotal(r.passMs, pass); });
  md += "\nGPU time by pass, every level, means of frames 2..N (0 where a frame skipped the pass):\n\n" +
        meansTable(run, scene, cameras, builds, "pass", passRows, 2);
  md += touchedTable(run, scene, cameras, builds);
  md += "\nEach level at the incremental run's last frame against the exact field of that moment (its band; above level "
        "0, the voxels within the view's reach, --cascade-view-margin):\n\n"
        "| camera | level | fine voxel | mean abs error (voxels) | max (voxels) | wrong sign |\n|---|---|---|---|---|---|\n";
  for (const CascadeLevelError& e : run.errors)
    if (e.scene == scene)
      md += fmt::format("| {} | {} | {:.4g} | {:.4f} | {:.2f} | {:.3f}% |\n", e.camera, e.level, e.voxelSize,
                        e.meanAbsVoxels, e.maxAbsVoxels, e.wrongSignPct);
  return md + "\n";
}

} // namespace

std::string cascadeReport(const BenchOptions& o, const CascadeRun& run) {
  const auto [coarse, fine] = frameSizeResolutions(o.frameSize);
  std::string md = fmt::format(
      "## Cascades: {} levels of coarse {} / fine {}, level 0 {} wide, {} refinement, x = {}\n\n"
      "Each scene's camera path at 30 fps, {} frames from t = 0 (walking) and from the moment it first moves faster "
      "than {} units/s (driving). Incremental: the levels follow the camera (a level whose box moved scrolls, its part of "
      "the scene cut again once it drifts past the slack) and each frame runs what changed; full rebuild (the anchor): the same frames with every pass of every level over "
      "its whole grid and every masked voxel refined. Medians of frames 2..N (the first builds every level), and the GPU time's mean and largest (a level moves in some frames only).\n\n",
      o.cascades, coarse, fine, o.cascadeExtent > 0.0 ? fmt::format("{:g} units", o.cascadeExtent) : "(default)",
      toString(o.refine), o.rays, o.frames, kDrivingSpeed);
  if (o.shade != std::pair<int, int>{0, 0})
    md += fmt::format("{}: the incremental frames again through the renderer, SDF shadows at {}x{} with the render "
                      "command's defaults and no read-back; its GPU time is the levels' passes and the shading's, the "
                      "whole GPU frame.\n\n",
                      shadedBuild(o), o.shade.first, o.shade.second);
  if (o.warmUpSeconds > 0.0)
    md += fmt::format("Each run starts after {:g} s of untimed full frames on levels of its own (--warm-up), so that a "
                    "GPU's clocks have risen.\n\n",
                    o.warmUpSeconds);
  for (const std::string& note : run.notes) md += "- " + note + "\n";
  if (!run.notes.empty()) md += "\n";
  std::vector<std::string> scenes;
  for (const CascadeRow& r : run.rows)
    if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
  for (const std::string& scene : scenes) md += sceneReport(run, scene);
  return md;
}

} // namespace rtsdf::bench
