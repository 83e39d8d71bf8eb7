#include "jobs/Bake.h"

#include "jobs/CascadeBake.h"
#include "jobs/JobSupport.h"
#include "reference/OpenVdbLevelSet.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefinePasses.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>

namespace rtsdf {
namespace fs = std::filesystem;

void BakeOptions::validate() const {
  pipeline.validate();
  validateKnobs(*this);
  // Rays mode signs the refined voxels by its rays' votes alone: with none, every sign would be outside.
  if (method == BakeMethod::Rtsdf && pipeline.mode == RefineMode::Rays && pipeline.rays == 0 &&
      pipeline.band.value > 0.0)
    throw SettingError("rays", "rays mode with 0 rays [x] casts no ray to sign the voxels it refines: give 1 ray "
                               "or more, or use the closest refinement (its nearest triangle's side signs them)");
  if (pipeline.cascades > 1 && method != BakeMethod::Rtsdf)
    throw SettingError("cascades", fmt::format("cascades {}: cascade levels are baked by the rtsdf method (compare "
                                               "--against exact checks each level)", pipeline.cascades));
  if (fullDomain && method != BakeMethod::Exact)
    throw SettingError("full domain", "a full-domain field needs the exact method (OpenVDB's meshToLevelSet builds "
                                      "a narrow band only)");
  if (method == BakeMethod::Rtsdf) return; // a band of 0 refines nothing but is still a bake
  if (!(pipeline.band.value > 0.0))
    throw SettingError("band", fmt::format("band {} must be positive and finite", pipeline.band));
  if (grid && method == BakeMethod::Rtsdf)
    throw SettingError("grid", "the rtsdf method builds its own coarse and fine grids (set the fine resolution)");
}

void setOutputResolution(BakeOptions& o, int res) {
  o.resolution = res;
  if (o.method == BakeMethod::Jfa) o.pipeline.coarseRes = res;
  if (o.method != BakeMethod::Rtsdf) return;
  o.pipeline.fineRes = res;
  o.pipeline.coarseRes = std::max(1, res / 2);
}

int outputResolution(const BakeOptions& o) {
  switch (o.method) {
  case BakeMethod::Rtsdf: return o.pipeline.fineRes;
  case BakeMethod::Jfa: return o.pipeline.coarseRes;
  default: return o.resolution;
  }
}

int bakeFrames(const BakeOptions& o) {
  if (o.frames > 0) return o.frames;
  return o.pipeline.mode == RefineMode::Closest && o.pipeline.rays == 0 ? 1 : 16;
}

bool bakeMethodUses(BakeMethod method, const std::string& setting) {
  const auto among = [&](std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return setting == n; });
  };
  // The settings of some methods only; every other setting (the resolution, the band, the time, ...) is read by
  // every method.
  if (among({"full domain", "sign method"})) return method == BakeMethod::Exact;
  if (among({"coarse resolution", "coarse method", "beta", "device"}))
    return method == BakeMethod::Jfa || method == BakeMethod::Rtsdf;
  if (among({"fine resolution", "rays", "alpha", "refinement mode", "closest search", "seed", "full recompute",
             "settle frames", "refresh period", "fine storage", "pool bricks", "frames", "cascades",
             "cascade extent", "cascade view margin"}))
    return method == BakeMethod::Rtsdf;
  return true;
}

BakeOptions bakeOptionsResolved(const BakeOptions& options, const Bounds& bounds) {
  BakeOptions o = options;
  const double voxel = o.grid ? o.grid->voxelSize : bounds.maxExtent() / std::max(1, outputResolution(o));
  o.pipeline = withLengthsResolved(o.pipeline, voxel);
  if (!o.fullDomain) requireBandOfAVoxel(o.pipeline.band, voxel);
  o.frames = bakeFrames(o);
  return o;
}

double fineLevelSetBand(const PipelineSettings& s, const GridSpec& fine) {
  return s.band > 0.0 ? double(s.band) : 3.0 * fine.voxelSize;
}

openvdb::FloatGrid::Ptr fineLevelSet(const SdfPipeline& pipe, const BakeOptions& o, double time) {
  const PipelineSettings& p = o.pipeline;
  auto grid = pipe.levelSet(float(fineLevelSetBand(p, pipe.fineSpec())));
  stampLevelSet(*grid, pipe.fineSpec(),
                {{"method", "rtsdf"}, {"scene", recordedScenePath(o.scene)}, {"coarse", p.coarseRes},
                 {"resolution", p.fineRes}, {"band", double(p.band)}, {"alpha", p.alpha}, {"rays", p.rays},
                 {"frames", o.frames}, {"refine", toString(p.mode)}, {"coarse_method", toString(p.coarseMethod)},
                 {"seed", std::int64_t(p.seed)}, {"time", time}, {"version", detail::version()}});
  return grid;
}

namespace {

BakeResult bakeRtsdf(const BakeOptions& o, const Scene& scene, const Bounds& bounds, const JobControl& control) {
  return runOnDevice(deviceContextOptions(o.device), [&](const gpu::VulkanContext& ctx) {
    SdfPipeline pipe(ctx, scene, bounds, o.pipeline);
    spdlog::info("coarse {}, fine {}", pipe.coarseSpec().describe(), pipe.fineSpec().describe());
    BakeResult r;
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < o.frames; ++f) {
      control.checkStop();
      r.lastFrame = pipe.runFrame(o.time);
      r.cutVoxels += r.lastFrame.cutVoxels;
      control.report("refining", std::uint64_t(f + 1), std::uint64_t(o.frames));
    }
    r.seconds = secondsSince(t0);
    throwOnValidationErrors(ctx);
    r.grid = fineLevelSet(pipe, o, o.time);
    r.spec = pipe.fineSpec();
    r.coarseSpec = pipe.coarseSpec();
    r.device = ctx.info().name;
    warnOfCutWalks(r.cutVoxels, r.device);
    return r;
  });
}

openvdb::FloatGrid::Ptr bakeCoarse(const BakeOptions& o, const SceneGeometry& geo, const GridSpec& spec,
                                   BakeResult& r) {
  return runOnDevice(deviceContextOptions(o.device), [&](const gpu::VulkanContext& ctx) {
    CoarseSdfSettings cs;
    cs.method = o.pipeline.coarseMethod;
    cs.beta = o.pipeline.beta;
    CoarseSdfBuilder builder(ctx);
    const CoarseSdf coarse = builder.build(geo, spec, cs);
    r.lastFrame.passMs = coarse.passMs;
    r.device = ctx.info().name;
    spdlog::info("GPU {}: {}", ctx.info().name, [&] {
      std::string t;
      for (const char* p : {VoxelizePass::kName, coarseTransformPass(cs.method), CoarseDistancePass::kName})
        t += fmt::format("{} {:.2f} ms  ", p, coarse.passTotal(p));
      return t;
    }());
    throwOnValidationErrors(ctx);
    return denseToLevelSet(coarse.distance, spec, float(o.pipeline.band));
  });
}

const char* signDescription(const BakeOptions& o) {
  switch (o.method) {
  case BakeMethod::Exact: return toString(o.sign);
  case BakeMethod::OpenVdb: return "openvdb flood fill";
  default: return "coarse shell: distance minus beta";
  }
}

/// The grid of exact, openvdb and jfa bakes: the one given, or the scene's bounds at the method's resolution;
/// checked against memory before anything is allocated (the full domain is dense; a band needs a pointer per 8^3
/// block).
GridSpec bakeGrid(const BakeOptions& o, const SceneGeometry& geo, double padding) {
  const GridSpec spec = o.grid ? *o.grid
                               : GridSpec::fromBounds(geo.bounds, o.method == BakeMethod::Jfa ? o.pipeline.coarseRes
                                                                                              : o.resolution, padding);
  if (!o.fullDomain) requireBandWithin(spec, o.pipeline.band);
  if (o.method == BakeMethod::Jfa) requireBetaWithin(spec, o.pipeline.beta);
  const std::uint64_t mem = physicalMemoryBytes();
  if (mem) checkDenseMemory(spec, o.fullDomain ? 8 : (o.method == BakeMethod::Jfa ? 24 : 1), mem / 2, "bake");
  spdlog::info("grid: {}, band {} ({:.1f} voxels){}", spec.describe(), o.pipeline.band,
               o.pipeline.band / spec.voxelSize, o.fullDomain ? ", full domain" : "");
  return spec;
}

BakeResult bakeOnGrid(const BakeOptions& o, const SceneGeometry& geo, const JobControl& control) {
  const double band = o.pipeline.band;
  const double padding = pipelinePadding(geo.bounds, o.pipeline);
  BakeResult r;
  r.spec = bakeGrid(o, geo, padding);
  const auto t0 = std::chrono::steady_clock::now();
  if (o.method == BakeMethod::Exact) {
    ExactSdfOptions opt;
    opt.band = o.fullDomain ? INFINITY : band;
    opt.sign = o.sign;
    opt.progress = false; // progress goes to the caller's control alone (a library call prints nothing itself)
    opt.control = &control;
    r.grid = exactSignedDistance(geo, r.spec, opt, &r.exact);
  } else if (o.method == BakeMethod::OpenVdb) {
    r.grid = openvdbLevelSet(geo, r.spec, band);
  } else {
    r.grid = bakeCoarse(o, geo, r.spec, r);
  }
  r.seconds = secondsSince(t0);
  const bool jfa = o.method == BakeMethod::Jfa;
  stampLevelSet(*r.grid, r.spec,
                {{"method", toString(o.method)},
                 {"scene", recordedScenePath(o.scene)},
                 {"resolution", jfa ? o.pipeline.coarseRes : o.resolution},
                 {"band", o.fullDomain ? double(INFINITY) : band},
                 {"padding", padding},
                 {"time", o.time},
                 {"sign", signDescription(o)},
                 {"coarse_method", jfa ? toString(o.pipeline.coarseMethod) : ""},
                 {"version", detail::version()}});
  return r;
}

BakeResult bakeValidated(const Scene& scene, const BakeOptions& given, const JobControl& control) {
  const std::string summary = detail::meshSummary(scene);
  const std::string name = given.scene.empty() ? "(scene in memory)" : given.scene;
  spdlog::info("{}: {}", name, summary);
  // The rtsdf method builds its own geometry per frame; the others bake this one.
  std::optional<SceneGeometry> geo;
  geo.emplace(buildSceneGeometry(scene, given.time));
  BakeResult r;
  if (given.method == BakeMethod::Rtsdf && given.pipeline.cascades > 1) {
    // Each level resolves the lengths in its own voxels (CascadeBake.h).
    BakeOptions levels = given;
    levels.frames = bakeFrames(given);
    geo.reset();
    r = bakeCascades(levels, scene, control);
    // The options in effect, lengths in scene units: level 0's (level i's band is 2^i times it).
    levels.pipeline = withLengthsResolved(levels.pipeline, r.spec.voxelSize);
    r.options = levels;
  } else {
    const BakeOptions options = bakeOptionsResolved(given, geo->bounds);
    if (options.method == BakeMethod::Rtsdf) {
      const Bounds bounds = geo->bounds;
      geo.reset();
      r = bakeRtsdf(options, scene, bounds, control);
    } else {
      r = bakeOnGrid(options, *geo, control);
    }
    r.options = options;
  }
  const BakeOptions& options = r.options;
  // A cascade level may lie in empty air (a camera above an open field): only all of them empty is an error.
  std::uint64_t active = r.grid->activeVoxelCount();
  for (const auto& level : r.levels) active += level->activeVoxelCount();
  if (!options.allowEmpty && active == 0)
    throw Error(fmt::format("{}: the {} level set on {} has no active voxel (band {:g} = {:.3g} voxels): widen the "
                            "band, raise the resolution or, to keep it, allow an empty result", name,
                            toString(options.method), r.spec.describe(), double(options.pipeline.band),
                            options.pipeline.band / r.spec.voxelSize));
  r.sceneSummary = summary;
  // The files read: writeBake never replaces one of them.
  if (!options.scene.empty()) r.inputs.push_back(options.scene);
  for (const Mesh& m : scene.meshes)
    if (!m.source.empty() && m.source.front() != '<') r.inputs.push_back(m.source);
  return r;
}

} // namespace

BakeResult bake(const BakeOptions& options, const JobControl& control) {
  options.validate(); // before reading the scene: bad settings are refused before any work
  return bakeValidated(loadScene(options.scene, options.meshLoad), options, control);
}

BakeResult bake(const Scene& scene, const BakeOptions& options, const JobControl& control) {
  options.validate();
  return bakeValidated(scene, options, control);
}

void writeBake(const BakeResult& result, const fs::path& path, const BakeOutputOptions& output) {
  checkOutputPath(path, ".vdb", result.inputs);
  openvdb::GridPtrVec grids;
  for (const auto& level : result.levels) {
    grids.push_back(level);
    if (output.fog) {
      grids.push_back(makeFogGrid(*level));
      grids.back()->setName("density_" + level->getName().substr(level->getName().rfind('_') + 1));
    }
  }
  if (result.levels.empty()) {
    grids.push_back(result.grid);
    if (output.fog) grids.push_back(makeFogGrid(*result.grid));
  }
  writeVdb(path, grids, output.vdb);
}

namespace {

std::string rtsdfReport(const BakeResult& r, const fs::path& output) {
  const BakeOptions& o = r.options;
  const PipelineSettings& p = o.pipeline;
  const FrameStats& st = r.lastFrame;
  // Every pass that ran, in recording order, a pass recorded several times once with its total.
  std::string passes;
  std::vector<std::string> seen;
  for (const auto& entry : st.passMs) {
    if (std::find(seen.begin(), seen.end(), entry.first) != seen.end()) continue;
    seen.push_back(entry.first);
    passes += fmt::format("{} {:.1f} ms, ", entry.first, st.passTotal(entry.first));
  }
  std::string t = fmt::format("scene      {}\n", o.scene);
  t += fmt::format("method     rtsdf ({} refinement, x = {}, alpha = {}, {} frames, {})\n", toString(p.mode), p.rays,
                   p.alpha, o.frames, toString(p.coarseMethod));
  t += fmt::format("coarse     {}\n", r.coarseSpec.describe());
  t += fmt::format("fine       {}\n", r.spec.describe());
  t += fmt::format("ray mask   {} coarse voxels, {} fine voxels (band {:.6g} = {:.2f} fine voxels)\n",
                   st.maskCoarseVoxels, st.maskFineVoxels, double(p.band), p.band / r.spec.voxelSize);
  if (r.cutVoxels)
    t += fmt::format("cut walks  {} voxel refinements ended by the device's loop budget (upper bounds)\n",
                     r.cutVoxels);
  t += fmt::format("last frame {}host (CPU) {:.1f} ms\n", passes, st.hostMs);
  t += fmt::format("time       {:.3f} s for {} frames on {}\n", r.seconds, o.frames, r.device);
  t += fmt::format("output     {} ({} active voxels)\n", output.string(), r.grid->activeVoxelCount());
  return t + cascadeReport(r);
}

} // namespace

std::string bakeReport(const BakeOptions&, const BakeResult& r, const fs::path& output,
                       const BakeOutputOptions& written) {
  const BakeOptions& o = r.options; // with its lengths in scene units
  if (o.method == BakeMethod::Rtsdf) return rtsdfReport(r, output);
  const double band = o.pipeline.band;
  const std::uint64_t active = r.grid->activeVoxelCount();
  std::error_code ec;
  const auto bytes = fs::file_size(output, ec);
  std::string t = fmt::format("scene      {}\n", o.scene);
  t += fmt::format("method     {}{}\n", toString(o.method),
                   o.method == BakeMethod::Exact ? fmt::format(" (sign: {})", toString(o.sign)) : "");
  t += fmt::format("grid       {}\n", r.spec.describe());
  t += fmt::format("band       {:.6g} scene units = {:.2f} voxels{}\n", band, band / r.spec.voxelSize,
                   o.fullDomain ? " (full domain: all voxels active)" : "");
  t += fmt::format("active     {} voxels of {} ({:.2f}%)\n", active, r.spec.voxelCount(),
                   100.0 * double(active) / double(r.spec.voxelCount()));
  if (o.method == BakeMethod::Exact && r.exact.windingQueries)
    t += fmt::format("sign       {} voxels signed by winding number (nearest mesh open)\n", r.exact.windingQueries);
  t += fmt::format("time       {:.3f} s\n", r.seconds);
  t += fmt::format("output     {} ({:.2f} MiB, grids: {}{})\n", output.string(), double(ec ? 0 : bytes) / 1048576.0,
                   r.grid->getName(), written.fog ? ", density" : "");
  return t;
}

} // namespace rtsdf
