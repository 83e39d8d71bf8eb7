#include "suites/SweepRunner.h"

#include "grid/GridSpec.h"
#include "jobs/JobSupport.h"
#include "grid/VdbIO.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "reference/OpenVdbLevelSet.h"
#include "scene/SceneGeometry.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefinePasses.h"
#include "util/Error.h"
#include "util/Settings.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <malloc.h>
#include <unistd.h>

namespace rtsdf::bench {
namespace fs = std::filesystem;
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return kNotMeasured;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The timings of a record: the median per pass over @a all but the first frame (the warm-up: it pays for
/// first-touch allocations); the first alone when there is no other.
void setTimings(SweepRecord& r, const std::vector<FrameStats>& all) {
  std::vector<FrameStats> frames(all.size() > 1 ? all.begin() + 1 : all.begin(), all.end());
  auto med = [&](auto get) {
    std::vector<double> v;
    for (const FrameStats& f : frames) v.push_back(get(f));
    return median(v);
  };
  r.voxelizeMs = med([](const FrameStats& f) { return f.passTotal(VoxelizePass::kName); });
  r.transformMs = med([](const FrameStats& f) { return coarseTransformMs(f.passMs); });
  r.distanceMs = med([](const FrameStats& f) { return f.passTotal(CoarseDistancePass::kName); });
  r.upsampleMs = med([](const FrameStats& f) { return f.passTotal(UpsamplePass::kName); });
  r.refineMs = med([](const FrameStats& f) { return f.refineMs(); });
  r.hostMs = med([](const FrameStats& f) { return f.hostMs; });
  r.frameMs = med([](const FrameStats& f) {
    double t = f.hostMs;
    for (const auto& [name, ms] : f.passMs) t += ms;
    return t;
  });
  r.maskVoxels = all.back().maskFineVoxels;
}

void setError(SweepRecord& r, const FieldError& e) {
  r.meanAbs = e.meanAbs;
  r.rms = e.rms;
  r.maxAbs = e.maxAbs;
  r.signErrorRate = e.signErrorRate();
  r.errorVoxels = e.voxels;
}

double toMiB(std::uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

} // namespace

void SweepRunOptions::validate() const {
  if (!(errorBand > 0.0) || !std::isfinite(errorBand))
    throw SettingError("error band", fmt::format("error band {} must be a positive length", errorBand));
  if (!(fps > 0.0) || !std::isfinite(fps)) throw SettingError("fps", fmt::format("fps {} must be positive", fps));
  requireInRange("shadow image width", shadowWidth, 8, 4096);
  requireInRange("shadow image height", shadowHeight, 8, 4096);
  requireInRange("repeats", repeats, 1, 100);
  requireInRange("truth samples", truthSamples, 1, 65536);
}

SweepRunner::SweepRunner(const Scene& scene, const SweepRunOptions& o) : mScene(scene), mOptions(o) {
  o.validate();
  for (const Instance& i : scene.instances) mAnimated |= i.animation.kind != Animation::Kind::None;
  // Fixed grids over every moment a Dynamic point visits, so history stays valid while objects move.
  const int frames = mAnimated ? std::max(1, o.animationFrames) : 1;
  for (int f = 0; f < frames; ++f) mBounds.add(buildSceneGeometry(scene, f / o.fps).bounds);
  if (mBounds.empty()) throw Error(fmt::format("{}: the scene has no geometry", scene.path));

  gpu::ContextOptions copt;
  copt.device = o.device;
  mCtx = std::make_unique<gpu::VulkanContext>(copt);

  if (o.shadows && scene.hasCamera && !scene.lights.empty()) {
    RenderSettings rs;
    rs.width = o.shadowWidth;
    rs.height = o.shadowHeight;
    rs.rayTraced.samples = o.truthSamples;
    spdlog::info("sweep: ray tracing the shadow truth at {}x{}, {} samples per pixel", rs.width, rs.height,
                 rs.rayTraced.samples);
    mTruth = std::make_unique<RenderedFrame>(renderRayTraced(scene, 0.0, rs));
  }
}

SweepRunner::~SweepRunner() = default;

void SweepRunner::finish() {
  mCtx->close();
  throwOnValidationErrors(*mCtx);
}

void SweepRunner::stopIfRequested() const {
  if (mOptions.stopRequested && mOptions.stopRequested()) throw SweepInterrupted();
}

const openvdb::FloatGrid& SweepRunner::exact(const GridSpec& spec, double time) {
  const std::string key = fmt::format("{} t={}", spec.describe(), time);
  if (auto it = mExactCache.find(key); it != mExactCache.end()) return *it->second;
  // Static points share a handful of grids; a Dynamic point visits each moment once.
  if (time != 0.0 || mExactCache.size() > 8) mExactCache.clear();
  ExactSdfOptions eo;
  eo.band = mOptions.errorBand;
  eo.progress = false;
  auto grid = exactSignedDistance(buildSceneGeometry(mScene, time), spec, eo);
  return *mExactCache.emplace(key, grid).first->second;
}

std::vector<SweepRecord> SweepRunner::run(const SweepPoint& p) {
  // What the point is measured against is not part of its cost: build the exact field first (cached).
  if (p.group != SweepGroup::Storage && p.group != SweepGroup::Dynamic) {
    try {
      // Only for grids the pipeline accepts: a refused point must not build a huge reference first.
      const PipelineMemory need = estimatePipelineMemory(mBounds, p.pipeline);
      checkPipelineMemory(need, memoryLimits(mCtx->info()));
      exact(need.fine, 0.0);
    } catch (const std::exception&) {
      // The point itself reports why it cannot run.
    }
  }
  // Freed memory the allocator kept would hide this point's own peak.
  malloc_trim(0);
  const bool peakReset = resetPeakResidentMemory();
  const std::uint64_t startBytes = currentResidentMemory();
  std::vector<SweepRecord> out;
  try {
    if (p.group == SweepGroup::Storage) out.push_back(runStorage(p));
    else if (p.anchor != AnchorKind::None) out.push_back(runAnchor(p));
    else out = runPipeline(p);
  } catch (const SweepInterrupted&) {
    throw;
  } catch (const std::bad_alloc&) {
    SweepRecord r;
    r.point = p;
    r.note = "out of memory";
    out = {r};
  } catch (const std::exception& e) {
    SweepRecord r;
    r.point = p;
    r.note = e.what();
    out = {r};
  }
  const std::uint64_t peakBytes = peakResidentMemory();
  for (SweepRecord& r : out) {
    r.peakMiB = toMiB(peakBytes);
    // Without a reset the peak may belong to an earlier point: then only the lifetime peak is known.
    if (peakReset) r.peakGrowthMiB = toMiB(peakBytes > startBytes ? peakBytes - startBytes : 0);
  }
  return out;
}

std::vector<SweepRecord> SweepRunner::runPipeline(const SweepPoint& p) {
  const bool dynamic = p.group == SweepGroup::Dynamic;
  // The sweep times each pass of a frame at the point's settings: a frame that skips the passes whose inputs did
  // not change (every still frame after the first) would time nothing. A full rebuild gives the same field.
  PipelineSettings settings = p.pipeline;
  settings.fullRebuild = true;
  std::unique_ptr<Renderer> renderer;
  std::unique_ptr<SdfPipeline> pipeline;
  RenderSettings rs;
  if (mTruth && !dynamic) {
    rs.width = mOptions.shadowWidth;
    rs.height = mOptions.shadowHeight;
    rs.technique = ShadowTechnique::Sdf;
    rs.pipeline = settings;
    renderer = std::make_unique<Renderer>(*mCtx, mScene, mBounds, rs);
  } else {
    pipeline = std::make_unique<SdfPipeline>(*mCtx, mScene, mBounds, settings);
  }
  const SdfPipeline& sdf = renderer ? *renderer->sdfPipeline() : *pipeline;

  std::vector<SweepRecord> out;
  std::vector<FrameStats> stats;
  RenderedFrame last;
  for (int f = 0; f < p.frames; ++f) {
    stopIfRequested();
    const double t = dynamic ? f / mOptions.fps : 0.0;
    if (renderer) {
      last = renderer->renderFrame(t, f + 1 == p.frames);
      stats.push_back(last.sdf);
    } else {
      stats.push_back(pipeline->runFrame(t));
    }
    if (dynamic) {
      SweepRecord r;
      r.point = p;
      r.frame = f;
      r.time = t;
      setTimings(r, {stats.back()});
      r.voxelSize = sdf.fineSpec().voxelSize;
      r.grid = fmt::format("{}x{}x{}", sdf.fineSpec().dims.x, sdf.fineSpec().dims.y, sdf.fineSpec().dims.z);
      setError(r, compareDenseWithReference(sdf.fineField(), sdf.fineSpec(), exact(sdf.fineSpec(), t)));
      out.push_back(r);
    }
  }
  if (dynamic) {
    // The last frame's timing is the median over the whole series, like static points.
    setTimings(out.back(), stats);
    return out;
  }
  SweepRecord r;
  r.point = p;
  r.frame = p.frames - 1;
  r.voxelSize = sdf.fineSpec().voxelSize;
  r.grid = fmt::format("{}x{}x{}", sdf.fineSpec().dims.x, sdf.fineSpec().dims.y, sdf.fineSpec().dims.z);
  stopIfRequested();
  setError(r, compareDenseWithReference(sdf.fineField(), sdf.fineSpec(), exact(sdf.fineSpec(), 0.0)));
  if (renderer) {
    const ShadowImageError e = compareWithTruth(mScene, last, *mTruth);
    r.shadowRmse = e.visibilityRmse;
    r.shadowPenumbraRmse = e.penumbraRmse;
    r.shadowFlip = e.flip;
  }
  // More frames for the timing alone: every frame does the same work, whatever its history.
  while (int(stats.size()) < mOptions.repeats + 1) {
    stopIfRequested();
    stats.push_back(renderer ? renderer->renderFrame(0.0, false).sdf : pipeline->runFrame(0.0));
  }
  setTimings(r, stats);
  out.push_back(r);
  return out;
}

GridSpec SweepRunner::fineSpecOf(const PipelineSettings& ps) const {
  // The pipeline's own fine grid for these settings (SdfPipeline pads by the band d).
  return pipelineGrids(mBounds, ps).second;
}

SweepRecord SweepRunner::runStorage(const SweepPoint& p) {
  const GridSpec spec = fineSpecOf(p.pipeline);
  const double band = p.storageBandVoxels > 0 ? p.storageBandVoxels * spec.voxelSize : mOptions.errorBand;
  SweepRecord r;
  r.point = p;
  r.voxelSize = spec.voxelSize;
  r.grid = fmt::format("{}x{}x{}", spec.dims.x, spec.dims.y, spec.dims.z);
  r.denseBytes = spec.voxelCount() * sizeof(float);
  ExactSdfOptions eo;
  eo.band = band;
  eo.progress = false;
  const auto t0 = std::chrono::steady_clock::now();
  openvdb::FloatGrid::Ptr grid = exactSignedDistance(buildSceneGeometry(mScene, 0.0), spec, eo);
  r.frameMs = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.maskVoxels = grid->activeVoxelCount();
  // The file a bake would write (float, blosc): its size on disk.
  const fs::path tmp = fs::temp_directory_path() / fmt::format("rtsdf-sweep-storage-{}.vdb", ::getpid());
  try {
    writeVdb(tmp, {grid}, VdbWriteOptions{});
    r.vdbBytes = fs::file_size(tmp);
  } catch (...) {
    fs::remove(tmp);
    throw;
  }
  fs::remove(tmp);
  return r;
}

SweepRecord SweepRunner::runAnchor(const SweepPoint& p) {
  // The same fine voxels as the pipeline with the same d, and a band of the same half-width.
  const double band = p.pipeline.band;
  const GridSpec spec = fineSpecOf(p.pipeline);
  const SceneGeometry geo = buildSceneGeometry(mScene, 0.0);
  SweepRecord r;
  r.point = p;
  r.voxelSize = spec.voxelSize;
  r.grid = fmt::format("{}x{}x{}", spec.dims.x, spec.dims.y, spec.dims.z);
  const openvdb::FloatGrid& reference = exact(spec, 0.0);
  openvdb::FloatGrid::Ptr grid;
  std::vector<double> ms;
  for (int k = 0; k < mOptions.repeats; ++k) {
    stopIfRequested();
    const auto t0 = std::chrono::steady_clock::now();
    if (p.anchor == AnchorKind::OpenVdb) {
      grid = openvdbLevelSet(geo, spec, band);
    } else {
      ExactSdfOptions eo;
      eo.band = band;
      eo.progress = false;
      grid = exactSignedDistance(geo, spec, eo);
    }
    ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  r.frameMs = median(ms);
  r.maskVoxels = grid->activeVoxelCount();
  setError(r, compareFields(reference, *grid));
  return r;
}

} // namespace rtsdf::bench
