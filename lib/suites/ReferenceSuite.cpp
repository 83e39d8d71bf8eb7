// `rtsdf bench --suite reference`: the exact SDF against OpenVDB's meshToLevelSet, and the open-mesh case.
#include "suites/SuiteTables.h"

#include "grid/GridSpec.h"
#include "jobs/JobSupport.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "reference/OpenVdbLevelSet.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

namespace rtsdf::bench {
namespace fs = std::filesystem;

namespace {

/// The exact SDF and OpenVDB's meshToLevelSet of @a geo on the same voxels and band, each timed (median of the
/// suite's repeats).
struct ExactAndOpenVdb {
  openvdb::FloatGrid::Ptr exact, openVdb;
  double exactSeconds = 0.0, openVdbSeconds = 0.0;
};
ExactAndOpenVdb timeExactAndOpenVdb(const BenchOptions& s, const SceneGeometry& geo, const GridSpec& spec,
                                    double band) {
  ExactSdfOptions opt;
  opt.band = band;
  opt.progress = false;
  ExactAndOpenVdb r;
  r.exactSeconds = medianSeconds(s.repeats, [&] { r.exact = exactSignedDistance(geo, spec, opt); });
  r.openVdbSeconds = medianSeconds(s.repeats, [&] { r.openVdb = openvdbLevelSet(geo, spec, band); });
  return r;
}

} // namespace

std::string referenceSuite(const BenchOptions& s, const JobControl& control) {
  std::string md = fmt::format("Median of {} runs.\n\n", s.repeats);
  md += "| scene | res | grid | band (voxels) | active voxels | exact (s) | OpenVDB meshToLevelSet (s) | "
        "exact / OpenVDB | OpenVDB vs exact: mean / max abs (voxels) | wrong sign |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  JobPoll poll(&control, "reference suite", s.scenes.size() * s.resolutions.size());
  for (const std::string& path : s.scenes) {
    const SceneGeometry geo = buildSceneGeometry(loadScene(path), 0.0);
    const double band = s.bandFraction * geo.bounds.maxExtent();
    for (int res : s.resolutions) {
      control.checkStop();
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, band);
      spdlog::info("bench {} at {}: {}", path, res, spec.describe());
      const ExactAndOpenVdb r = timeExactAndOpenVdb(s, geo, spec, band);
      const double tExact = r.exactSeconds, tVdb = r.openVdbSeconds;
      const FieldError err = compareFields(*r.openVdb, *r.exact);
      md += fmt::format("| {} | {} | {}x{}x{} | {:.1f} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} / {:.2f} | {:.3f}% |\n",
                        fs::path(path).filename().string(), res, spec.dims.x, spec.dims.y, spec.dims.z,
                        band / spec.voxelSize, r.exact->activeVoxelCount(), tExact, tVdb, tExact / tVdb, err.meanAbs,
                        err.maxAbs, 100.0 * err.signErrorRate());
      spdlog::info("exact {:.3f} s, OpenVDB {:.3f} s, ratio {:.2f}", tExact, tVdb, tExact / tVdb);
      poll.done();
    }
  }
  return md;
}

std::string openMeshCase(const BenchOptions& s, const JobControl& control) {
  Scene scene = loadScene(bundledMesh("bunny.obj"));
  const Bounds bounds = buildSceneGeometry(scene, 0.0).bounds;
  scene.meshes[0] = cutHoles(subdivideMesh(scene.meshes[0], 3), 12, float(0.03 * bounds.maxExtent()));
  scene.meshReports[0] = validateMesh(scene.meshes[0]);
  const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
  std::string md = fmt::format("\nOpen mesh: the bunny split in four 3 times with 12 holes cut ({} triangles, {} "
                               "boundary edges). exact: the default sign rule (winding number on the rim only); "
                               "winding everywhere: the rule before it, one run; wrong sign: exact vs that.\n\n",
                               geo.triangleCount(), scene.meshReports[0].boundaryEdges);
  md += "| res | band (voxels) | active voxels | exact (s) | OpenVDB (s) | exact / OpenVDB | winding everywhere (s) | "
        "wrong sign vs winding everywhere | OpenVDB vs exact: mean / max abs (voxels) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  JobPoll poll(&control, "reference suite, open mesh", 2 * s.resolutions.size());
  for (int res : s.resolutions)
    for (double bandVoxels : {3.0, s.bandFraction * res}) {
      control.checkStop();
      const double band = bandVoxels * bounds.maxExtent() / res;
      const GridSpec spec = GridSpec::fromBounds(geo.bounds, res, band);
      const ExactAndOpenVdb r = timeExactAndOpenVdb(s, geo, spec, band);
      const openvdb::FloatGrid::Ptr& exact = r.exact;
      const double tExact = r.exactSeconds, tVdb = r.openVdbSeconds;
      ExactSdfOptions opt;
      opt.band = band;
      opt.progress = false;
      opt.sign = SignMethod::WindingNumber;
      openvdb::FloatGrid::Ptr winding;
      const double tWinding = medianSeconds(1, [&] { winding = exactSignedDistance(geo, spec, opt); });
      const FieldError signs = compareFields(*exact, *winding), err = compareFields(*r.openVdb, *exact);
      md += fmt::format("| {} | {:.1f} | {} | {:.3f} | {:.3f} | {:.2f} | {:.3f} | {:.4f}% | {:.3f} / {:.2f} |\n", res,
                        bandVoxels, exact->activeVoxelCount(), tExact, tVdb, tExact / tVdb, tWinding,
                        100.0 * signs.signErrorRate(), err.meanAbs, err.maxAbs);
      spdlog::info("open mesh at {}, band {:.1f} voxels: exact {:.3f} s, OpenVDB {:.3f} s, winding {:.3f} s, {} wrong "
                   "signs", res, bandVoxels, tExact, tVdb, tWinding, signs.signMismatches);
      poll.done();
    }
  return md;
}

} // namespace rtsdf::bench
