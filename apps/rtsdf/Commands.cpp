#include "Commands.h"

#include "grid/GridSpec.h"
#include "grid/VdbIO.h"
#include "gpu/EmbeddedShaders.h"
#include "gpu/VulkanContext.h"
#include "metrics/FieldError.h"
#include "reference/OpenVdbLevelSet.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/CoarseSdf.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "util/Progress.h"

#include <assimp/version.h>
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <oneapi/tbb/version.h>
#include <openvdb/version.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace rtsdf::app {
namespace fs = std::filesystem;

void checkOutputPath(const std::string& path) {
  const fs::path p(path);
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) throw Error(fmt::format("{}: output folder '{}' does not exist", path, dir.string()));
  if (fs::is_directory(p, ec)) throw Error(fmt::format("{}: is a folder, not a file", path));
}

namespace {

std::string meshSummary(const Scene& scene) {
  std::size_t tris = 0, dropped = 0, open = 0;
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    tris += scene.meshReports[i].triangles;
    dropped += scene.meshReports[i].degenerateDropped;
    open += scene.meshReports[i].watertight() ? 0 : 1;
  }
  return fmt::format("{} meshes ({} open), {} instances, {} triangles, {} zero-area dropped", scene.meshes.size(), open,
                     scene.instances.size(), tris, dropped);
}

} // namespace

PipelineSettings pipelineSettings(const BakeSettings& s) {
  PipelineSettings p;
  p.coarseRes = s.coarse;
  p.fineRes = s.fine;
  p.band = s.band;
  p.alpha = s.alpha;
  p.rays = s.rays;
  p.mode = parseRefineMode(s.refine);
  p.variant = parseJfaVariant(s.jfaVariant);
  p.beta = s.beta;
  p.seed = s.seed;
  p.validate();
  return p;
}

namespace {

/// The fine SDF's narrow band as a level set (band d; at d = 0 three fine voxels, so the file is valid).
openvdb::FloatGrid::Ptr fineLevelSet(const SdfPipeline& pipe, const BakeSettings& s, double time) {
  const double band = s.band > 0.0 ? s.band : 3.0 * pipe.fineSpec().voxelSize;
  auto grid = denseToLevelSet(pipe.fineField(), pipe.fineSpec(), float(band));
  stampLevelSet(*grid, pipe.fineSpec(),
                {{"method", "rtsdf"}, {"scene", s.scene}, {"coarse", std::to_string(s.coarse)},
                 {"resolution", std::to_string(s.fine)}, {"band", fmt::format("{}", s.band)},
                 {"alpha", fmt::format("{}", s.alpha)}, {"rays", std::to_string(s.rays)},
                 {"frames", std::to_string(s.frames)}, {"refine", s.refine}, {"jfa", s.jfaVariant},
                 {"seed", std::to_string(s.seed)}, {"time", fmt::format("{}", time)}, {"version", RTSDF_VERSION}});
  return grid;
}

std::string passSummary(const FrameStats& st) {
  std::string t;
  for (const char* p : {VoxelizePass::kName, JumpFloodPass::kName, CoarseDistancePass::kName,
                        SdfPipeline::kUpsampleName, SdfPipeline::kRefineName})
    t += fmt::format("{} {:.1f} ms, ", p, st.passTotal(p));
  return t + fmt::format("mirror (CPU) {:.1f} ms", st.mirrorMs);
}

int runBakeRtsdf(const BakeSettings& s) {
  checkOutputPath(s.output);
  if (s.frames < 1) throw Error(fmt::format("--frames {} must be at least 1", s.frames));
  const PipelineSettings ps = pipelineSettings(s);
  const Scene scene = loadScene(s.scene);
  spdlog::info("{}: {}", s.scene, meshSummary(scene));
  gpu::ContextOptions copt;
  copt.device = s.device;
  gpu::VulkanContext ctx(copt);
  SdfPipeline pipe(ctx, scene, buildSceneGeometry(scene, s.time).bounds, ps);
  spdlog::info("coarse {}, fine {}", pipe.coarseSpec().describe(), pipe.fineSpec().describe());
  FrameStats st;
  Progress progress("refining", std::uint64_t(s.frames));
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < s.frames; ++f) {
    st = pipe.runFrame(s.time);
    progress.add();
  }
  progress.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (ctx.validationErrors())
    throw Error(fmt::format("Vulkan validation reported {} error(s); last: {}", ctx.validationErrors(),
                            ctx.lastValidationMessage()));
  auto grid = fineLevelSet(pipe, s, s.time);
  writeVdb(s.output, {grid}, {});
  fmt::print("scene      {}\n", s.scene);
  fmt::print("method     rtsdf ({} refinement, x = {}, alpha = {}, {} frames, {})\n", s.refine, s.rays, s.alpha,
             s.frames, s.jfaVariant);
  fmt::print("coarse     {}\n", pipe.coarseSpec().describe());
  fmt::print("fine       {}\n", pipe.fineSpec().describe());
  fmt::print("ray mask   {} coarse voxels, {} fine voxels (band {})\n", st.maskCoarseVoxels, st.maskFineVoxels, s.band);
  fmt::print("last frame {}\n", passSummary(st));
  fmt::print("time       {:.3f} s for {} frames on {}\n", seconds, s.frames, ctx.info().name);
  fmt::print("output     {} ({} active voxels)\n", s.output, grid->activeVoxelCount());
  return 0;
}

} // namespace

int runAnimate(const AnimateSettings& a) {
  if (!a.csv.empty()) checkOutputPath(a.csv);
  if (!a.vdbDir.empty() && !fs::is_directory(a.vdbDir))
    throw Error(fmt::format("--vdb-dir {}: folder does not exist", a.vdbDir));
  if (a.frames < 1) throw Error(fmt::format("--frames {} must be at least 1", a.frames));
  if (!(a.fps > 0.0) || !std::isfinite(a.fps)) throw Error(fmt::format("--fps {} must be positive", a.fps));
  const PipelineSettings ps = pipelineSettings(a.pipeline);
  const Scene scene = loadScene(a.scene);
  std::size_t focusIndex = scene.instances.size();
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].name == a.focus) focusIndex = i;
  if (!a.focus.empty() && focusIndex == scene.instances.size())
    throw Error(fmt::format("--focus: {} has no instance named '{}'", a.scene, a.focus));
  // Grids fixed over the whole animation: the union of the scene's bounds at every frame.
  Bounds bounds;
  for (int f = 0; f < a.frames; ++f) bounds.add(buildSceneGeometry(scene, f / a.fps).bounds);
  gpu::ContextOptions copt;
  copt.device = a.pipeline.device;
  gpu::VulkanContext ctx(copt);
  SdfPipeline pipe(ctx, scene, bounds, ps);
  spdlog::info("coarse {}, fine {}", pipe.coarseSpec().describe(), pipe.fineSpec().describe());
  // --focus: the box the instance sweeps over the animation, grown by the band, in fine index space.
  openvdb::CoordBBox focusBox;
  if (!a.focus.empty()) {
    const std::size_t idx = focusIndex;
    Bounds swept;
    for (int f = 0; f < a.frames; ++f) {
      const SceneGeometry g = buildSceneGeometry(scene, f / a.fps);
      for (const glm::vec3& p : g.meshes[idx].positions) swept.add(glm::dvec3(p));
    }
    const glm::dvec3 lo = pipe.fineSpec().worldToIndex(swept.min - ps.band);
    const glm::dvec3 hi = pipe.fineSpec().worldToIndex(swept.max + ps.band);
    focusBox = openvdb::CoordBBox(openvdb::Coord(int(std::floor(lo.x)), int(std::floor(lo.y)), int(std::floor(lo.z))),
                                  openvdb::Coord(int(std::ceil(hi.x)), int(std::ceil(hi.y)), int(std::ceil(hi.z))));
  }
  std::string csv = "frame,time,mask_coarse,mask_fine,voxelize_ms,jump_flood_ms,distance_ms,upsample_ms,refine_ms,"
                    "mirror_ms,band_voxels,mean_abs_error_voxels,max_abs_error_voxels,wrong_sign_rate\n";
  fmt::print("{:>5} {:>7} {:>10} {:>10} {:>10} {:>10} {:>12} {:>12} {:>10}\n", "frame", "time", "mask", "GPU ms",
             "mirror ms", "band", "mean err", "max err", "wrong sign");
  for (int f = 0; f < a.frames; ++f) {
    const double t = f / a.fps;
    const FrameStats st = pipe.runFrame(t);
    double gpuMs = 0.0;
    for (const auto& [n, ms] : st.passMs) gpuMs += ms;
    FieldError err;
    if (a.error) {
      // Against the exact field of the same moment, over the fine voxels in the band (|exact| <= d).
      const SceneGeometry geo = buildSceneGeometry(scene, t);
      ExactSdfOptions eo;
      eo.band = ps.band > 0.0 ? ps.band : 3.0 * pipe.fineSpec().voxelSize;
      eo.progress = false;
      const auto exact = exactSignedDistance(geo, pipe.fineSpec(), eo);
      if (!a.focus.empty()) exact->clip(focusBox);
      const auto fine = denseToLevelSet(pipe.fineField(), pipe.fineSpec(), float(eo.band));
      fine->setTransform(exact->transform().copy());
      err = compareFields(*exact, *fine);
    }
    fmt::print("{:>5} {:>7.3f} {:>10} {:>10.1f} {:>10.1f} {:>10} {:>12.4f} {:>12.3f} {:>9.3f}%\n", f, t,
               st.maskFineVoxels, gpuMs, st.mirrorMs, err.voxels, err.meanAbs, err.maxAbs, 100.0 * err.signErrorRate());
    csv += fmt::format("{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{},{:.5f},{:.4f},{:.6f}\n", f, t,
                       st.maskCoarseVoxels, st.maskFineVoxels, st.passTotal(VoxelizePass::kName),
                       st.passTotal(JumpFloodPass::kName), st.passTotal(CoarseDistancePass::kName),
                       st.passTotal(SdfPipeline::kUpsampleName), st.passTotal(SdfPipeline::kRefineName), st.mirrorMs,
                       err.voxels, err.meanAbs, err.maxAbs, err.signErrorRate());
    if (!a.vdbDir.empty()) {
      BakeSettings b = a.pipeline;
      b.scene = a.scene;
      auto grid = fineLevelSet(pipe, b, t);
      writeVdb(fs::path(a.vdbDir) / fmt::format("frame{:04d}.vdb", f), {grid}, {});
    }
  }
  if (ctx.validationErrors())
    throw Error(fmt::format("Vulkan validation reported {} error(s); last: {}", ctx.validationErrors(),
                            ctx.lastValidationMessage()));
  if (!a.csv.empty()) writeTextAtomically(a.csv, csv);
  return 0;
}

int runBake(const BakeSettings& s) {
  checkOutputPath(s.output);
  const BakeMethod method = s.method == "openvdb" ? BakeMethod::OpenVdb
                            : s.method == "jfa"   ? BakeMethod::Jfa
                            : s.method == "rtsdf" ? BakeMethod::Rtsdf
                                                  : BakeMethod::Exact;
  if (method == BakeMethod::Rtsdf) return runBakeRtsdf(s);
  if (s.fullDomain && method != BakeMethod::Exact)
    throw Error("--full needs --method exact (OpenVDB's meshToLevelSet builds a narrow band only)");
  const SignMethod sign = parseSignMethod(s.sign);
  if (!std::isfinite(s.time)) throw Error("--time must be finite");
  if (!std::isfinite(s.band) || !(s.band > 0.0)) throw Error(fmt::format("--band {} must be positive and finite", s.band));
  if (std::isnan(s.padding) || std::isinf(s.padding))
    throw Error(fmt::format("--padding {} must be finite", s.padding));

  const Scene scene = loadScene(s.scene);
  spdlog::info("{}: {}", s.scene, meshSummary(scene));
  const SceneGeometry geo = buildSceneGeometry(scene, s.time);
  const double padding = s.padding >= 0.0 ? s.padding : s.band;
  const GridSpec spec =
      GridSpec::fromBounds(geo.bounds, method == BakeMethod::Jfa ? s.coarse : s.resolution, padding);
  // Refuse before allocating: the full domain is dense; a band needs a pointer per 8^3 block at least.
  const std::uint64_t mem = physicalMemoryBytes();
  if (mem) checkDenseMemory(spec, s.fullDomain ? 8 : (method == BakeMethod::Jfa ? 24 : 1), mem / 2, "bake");
  spdlog::info("grid: {}, band {} ({:.1f} voxels){}", spec.describe(), s.band, s.band / spec.voxelSize,
               s.fullDomain ? ", full domain" : "");

  const auto t0 = std::chrono::steady_clock::now();
  openvdb::FloatGrid::Ptr grid;
  ExactSdfStats stats;
  if (method == BakeMethod::Exact) {
    ExactSdfOptions opt;
    opt.band = s.fullDomain ? INFINITY : s.band;
    opt.sign = sign;
    grid = exactSignedDistance(geo, spec, opt, &stats);
  } else if (method == BakeMethod::OpenVdb) {
    grid = openvdbLevelSet(geo, spec, s.band);
  } else {
    gpu::ContextOptions copt;
    copt.device = s.device;
    gpu::VulkanContext ctx(copt);
    CoarseSdfSettings cs;
    cs.variant = parseJfaVariant(s.jfaVariant);
    cs.beta = s.beta;
    CoarseSdfBuilder builder(ctx);
    const CoarseSdf coarse = builder.build(geo, spec, cs);
    spdlog::info("GPU {}: {}", ctx.info().name, [&] {
      std::string t;
      for (const char* p : {VoxelizePass::kName, JumpFloodPass::kName, CoarseDistancePass::kName})
        t += fmt::format("{} {:.2f} ms  ", p, coarse.passTotal(p));
      return t;
    }());
    if (ctx.validationErrors())
      throw Error(fmt::format("Vulkan validation reported {} error(s); last: {}", ctx.validationErrors(),
                              ctx.lastValidationMessage()));
    grid = denseToLevelSet(coarse.distance, spec, float(s.band));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  stampLevelSet(*grid, spec,
                {{"method", s.method},
                 {"scene", s.scene},
                 {"resolution", std::to_string(method == BakeMethod::Jfa ? s.coarse : s.resolution)},
                 {"band", fmt::format("{}", s.fullDomain ? INFINITY : s.band)},
                 {"padding", fmt::format("{}", padding)},
                 {"time", fmt::format("{}", s.time)},
                 {"sign", method == BakeMethod::Exact     ? toString(sign)
                          : method == BakeMethod::OpenVdb ? "openvdb flood fill"
                                                          : "coarse shell: distance minus beta"},
                 {"jfa", method == BakeMethod::Jfa ? s.jfaVariant : ""},
                 {"version", RTSDF_VERSION}});
  openvdb::GridPtrVec grids{grid};
  if (s.fog) grids.push_back(makeFogGrid(*grid));
  VdbWriteOptions wopt;
  wopt.halfFloat = s.halfFloat;
  wopt.compression = s.compression == "zip" ? VdbCompression::Zip
                     : s.compression == "none" ? VdbCompression::None
                                               : VdbCompression::Blosc;
  writeVdb(s.output, grids, wopt);

  const auto bytes = fs::file_size(s.output);
  fmt::print("scene      {}\n", s.scene);
  fmt::print("method     {}{}\n", s.method, method == BakeMethod::Exact ? fmt::format(" (sign: {})", toString(sign)) : "");
  fmt::print("grid       {}\n", spec.describe());
  fmt::print("band       {} scene units = {:.2f} voxels{}\n", s.band, s.band / spec.voxelSize,
             s.fullDomain ? " (full domain: all voxels active)" : "");
  fmt::print("active     {} voxels of {} ({:.2f}%)\n", grid->activeVoxelCount(), spec.voxelCount(),
             100.0 * double(grid->activeVoxelCount()) / double(spec.voxelCount()));
  if (method == BakeMethod::Exact && stats.windingQueries)
    fmt::print("sign       {} voxels signed by winding number (nearest mesh open)\n", stats.windingQueries);
  fmt::print("time       {:.3f} s\n", seconds);
  fmt::print("output     {} ({:.2f} MiB, grids: {}{})\n", s.output, double(bytes) / (1024.0 * 1024.0),
             grid->getName(), s.fog ? ", density" : "");
  return 0;
}

int runInfo() {
  fmt::print("rtsdf {}\n", RTSDF_VERSION);
  fmt::print("OpenVDB {} (ABI {}), Embree {}, oneTBB {}, assimp {}.{}.{}\n", OPENVDB_LIBRARY_VERSION_STRING,
             OPENVDB_ABI_VERSION_NUMBER, RTC_VERSION_STRING, TBB_VERSION_STRING, aiGetVersionMajor(),
             aiGetVersionMinor(), aiGetVersionPatch());
  fmt::print("embedded shaders:");
  for (const auto& n : gpu::embeddedShaderNames()) fmt::print(" {}", n);
  fmt::print("\n");
  std::vector<gpu::DeviceInfo> devices;
  try {
    devices = gpu::listDevices();
  } catch (const Error& e) {
    fmt::print("Vulkan: {}\n", e.what());
    return 1;
  }
  const std::uint32_t chosen = gpu::chooseDevice(devices, "");
  fmt::print("Vulkan devices ({}):\n", devices.size());
  for (const auto& d : devices) {
    fmt::print("  [{}] {}{} ({}, Vulkan {}.{}.{}, driver {})\n", d.index, d.name, d.index == chosen ? " *default*" : "",
               d.typeName, VK_VERSION_MAJOR(d.apiVersion), VK_VERSION_MINOR(d.apiVersion),
               VK_VERSION_PATCH(d.apiVersion), d.driver);
    fmt::print("      maxStorageBufferRange {} MiB, shared memory {} KiB, workgroup invocations {}, "
               "3D image {}, subgroup {}, timestamps {} ({} ns/tick), device-local {} MiB\n",
               d.maxStorageBufferRange >> 20, d.maxComputeSharedMemory >> 10, d.maxComputeInvocations,
               d.maxImageDimension3D, d.subgroupSize, d.computeTimestamps ? "yes" : "no", d.timestampPeriodNs,
               d.deviceLocalBytes >> 20);
  }
  return 0;
}

int runCompare(const CompareSettings& s) {
  const auto a = readLevelSet(s.a);
  const auto b = readLevelSet(s.b);
  FieldError e;
  try {
    e = compareFields(*a, *b);
  } catch (const Error& err) {
    throw Error(fmt::format("{} vs {}: {}", s.a, s.b, err.what()));
  }
  fmt::print("A          {} ({} active voxels)\n", s.a, a->activeVoxelCount());
  fmt::print("B          {} ({} active voxels)\n", s.b, b->activeVoxelCount());
  fmt::print("voxel size {}\n", a->voxelSize()[0]);
  fmt::print("compared   {} voxels active in both ({} only in A, {} only in B)\n", e.voxels, e.onlyInA, e.onlyInB);
  fmt::print("|A - B|    mean {:.4f}, RMS {:.4f}, max {:.4f} voxels\n", e.meanAbs, e.rms, e.maxAbs);
  fmt::print("sign       {} voxels disagree ({:.4f}%)\n", e.signMismatches, 100.0 * e.signErrorRate());
  return 0;
}

} // namespace rtsdf::app
