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
#include "util/Error.h"

#include <assimp/version.h>
#include <embree3/rtcore_config.h>
#include <fmt/format.h>
#include <oneapi/tbb/version.h>
#include <openvdb/version.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>

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

int runBake(const BakeSettings& s) {
  checkOutputPath(s.output);
  const BakeMethod method = s.method == "openvdb" ? BakeMethod::OpenVdb
                            : s.method == "jfa"   ? BakeMethod::Jfa
                                                  : BakeMethod::Exact;
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
