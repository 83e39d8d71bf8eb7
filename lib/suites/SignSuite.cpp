// `rtsdf bench --suite sign`: every method's signs on meshes whose faces lie (inside-out, flipped at random, parts
// passing through each other, an inner shell) and on open scans of several pieces, in scene units and in
// millimetres, against the clean solid (its closed form, or the exact field of the closed mesh a scan was made from)
// and against OpenVDB's meshToLevelSet in the same run.
#include "suites/SuiteTables.h"

#include "jobs/Bake.h"
#include "jobs/JobSupport.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "scene/Mesh.h"
#include "scene/MeshIO.h"
#include "scene/ScanMeshes.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <functional>
#include <memory>

namespace rtsdf::bench {
namespace {

/// One mesh that lies about its solid, and the closed form of the solid it stands for (in units of 1).
struct SignCase {
  std::string name;
  Mesh mesh;
  std::function<double(const glm::dvec3&)> solid;
};

/// @a m with every @a every-th triangle's corners reversed (1: all of them, inside-out).
Mesh reversed(Mesh m, int every) {
  for (std::size_t t = 0; t < m.triangles.size(); t += std::size_t(every)) std::swap(m.triangles[t].y, m.triangles[t].z);
  return m;
}

/// @a a with @a b's triangles appended, moved by @a offset.
Mesh joined(Mesh a, const Mesh& b, const glm::vec3& offset) {
  const unsigned base = unsigned(a.positions.size());
  for (const glm::vec3& p : b.positions) a.positions.push_back(p + offset);
  for (const glm::uvec3& t : b.triangles) a.triangles.push_back(t + glm::uvec3(base));
  return a;
}

/// The exact field of the closed @a mesh as a solid's signed distance (for scans made from it).
std::function<double(const glm::dvec3&)> exactSolid(Mesh mesh) {
  validateMesh(mesh);
  auto geometry = std::make_shared<SceneGeometry>();
  WorldMesh w;
  w.positions = mesh.positions;
  w.triangles = mesh.triangles;
  w.watertight = true;
  for (const glm::vec3& p : w.positions) geometry->bounds.add(glm::dvec3(p));
  geometry->meshes.push_back(std::move(w));
  auto field = std::make_shared<ExactDistanceField>(*geometry);
  return [geometry, field](const glm::dvec3& p) { return double(field->signedDistance(glm::vec3(p))); };
}

/// Open scans of several pieces: a sphere in eight separated patches (as is and with a fifth of its faces flipped)
/// and the bunny as a scan in pieces (two halves, a non-manifold fin, six floating discs, 12 holes).
std::vector<SignCase> openScanCases() {
  const auto ball = [](const glm::dvec3& p) { return glm::length(p) - 1.0; };
  const Mesh bunny = loadMeshFile(bundledMesh("bunny.obj"));
  const Mesh patches = makeSphereInPatches(5, 0.02f);
  return {{"open scan: sphere in 8 patches", patches, ball},
          {"open scan: sphere in 8 patches, 20% of faces flipped", reversed(patches, 5), ball},
          {"open scan: bunny in pieces (non-manifold fin, fragments)", makeScanInPieces(subdivideMesh(bunny, 1), 12),
           exactSolid(bunny)}};
}

std::vector<SignCase> signCases() {
  const Mesh sphere = makeSphereMesh(1.0f, 4);
  const auto ball = [](const glm::dvec3& p) { return glm::length(p) - 1.0; };
  const glm::vec3 offset(1.2f, 0.2f, 0.0f);
  const auto twoBalls = [offset](const glm::dvec3& p) {
    return std::min(glm::length(p) - 1.0, glm::length(p - glm::dvec3(offset)) - 1.0);
  };
  const auto torus = [](const glm::dvec3& p) {
    return glm::length(glm::dvec2(glm::length(glm::dvec2(p.x, p.z)) - 1.0, p.y)) - 0.35;
  };
  Mesh shell = makeSphereMesh(0.5f, 3); // an inner shell facing inward, as a hollow ball's cavity would
  return {{"sphere, clean", sphere, ball},
          {"sphere, inside-out", reversed(sphere, 1), ball},
          {"sphere, 1% of faces flipped", reversed(sphere, 100), ball},
          {"sphere, 20% of faces flipped", reversed(sphere, 5), ball},
          {"sphere, 50% of faces flipped", reversed(sphere, 2), ball},
          {"torus, inside-out", reversed(makeTorusMesh(1.0f, 0.35f, 96, 32), 1), torus},
          {"two spheres through each other", joined(sphere, reversed(sphere, 1), offset), twoBalls},
          {"sphere with an inner shell", joined(sphere, reversed(shell, 1), glm::vec3(0.0f)), ball}};
}

/// The cases whose name contains one of @a names (every case when @a names is empty): `bench --suite sign open`
/// runs the open scans alone.
/// @throw SettingError when a name selects no case.
std::vector<SignCase> selectedCases(const std::vector<std::string>& names) {
  std::vector<SignCase> all = signCases(), chosen;
  for (SignCase& c : openScanCases()) all.push_back(std::move(c));
  for (SignCase& c : all)
    if (names.empty() || std::any_of(names.begin(), names.end(), [&](const std::string& n) {
          return c.name.find(n) != std::string::npos;
        }))
      chosen.push_back(std::move(c));
  if (chosen.empty())
    throw SettingError("scenes", fmt::format("no case of the sign suite is named after '{}'", fmt::join(names, "', '")));
  return chosen;
}

/// A method of the table: a bake's method and, for rtsdf, its refinement.
struct SignMethodRow {
  const char* name;
  BakeMethod method;
  RefineMode mode = RefineMode::Closest;
  int rays = 0, frames = 1;
};
// OpenVDB first: every other row is compared with it and timed against it.
const SignMethodRow kSignMethods[] = {{"OpenVDB", BakeMethod::OpenVdb},
                                      {"exact", BakeMethod::Exact},
                                      {"closest x = 0", BakeMethod::Rtsdf, RefineMode::Closest, 0, 1},
                                      {"closest x = 1", BakeMethod::Rtsdf, RefineMode::Closest, 1, 4},
                                      {"rays x = 10", BakeMethod::Rtsdf, RefineMode::Rays, 10, 16}};

/// The scene of @a mesh scaled by @a unit, oriented as a load would (validateMesh).
Scene sceneOf(const SignCase& c, double unit) {
  Scene scene;
  scene.path = c.name;
  Mesh m = c.mesh;
  for (glm::vec3& p : m.positions) p *= float(unit);
  m.name = m.source = c.name;
  scene.meshReports.push_back(validateMesh(m));
  scene.meshes.push_back(std::move(m));
  scene.instances.push_back(Instance{c.name, 0, {}, {}});
  return scene;
}

} // namespace

std::string signSuite(const BenchOptions& s, const JobControl& control) {
  const int res = s.resolutions.empty() ? 96 : s.resolutions.front();
  if (res < 16) // the band of 3 voxels is 3 E / (res - 6) scene units: a few voxels across leave no band
    throw SettingError("resolution", fmt::format("the sign suite needs at least 16 voxels across, not {}", res));
  std::string md = fmt::format(
      "Fine grid {} voxels across (rtsdf: coarse {}), band 3 voxels, each mesh in units of 1 and of 1000 (millimetres). "
      "Wrong sign: active voxels farther than 0.1 voxel from the clean solid's surface whose sign differs from its "
      "closed form (for the bunny scan: the exact field of the closed bunny it was cut from); error: |field - clean "
      "solid| in voxels (the tessellation's own is below 0.02); vs OpenVDB: the sign disagreement with OpenVDB's "
      "meshToLevelSet on the same voxels. Time: one run; time / OpenVDB: against OpenVDB's bake of the same mesh "
      "and unit.\n\n", res, res / 2);
  md += "| mesh | unit | repaired at load | method | wrong sign | mean / max error (voxels) | vs OpenVDB | time (s) | "
        "time / OpenVDB |\n|---|---|---|---|---|---|---|---|---|\n";
  const std::vector<SignCase> cases = selectedCases(s.scenes);
  JobPoll poll(&control, "sign suite", 2 * cases.size() * std::size(kSignMethods)); // two units per case
  for (const SignCase& c : cases)
    for (double unit : {1.0, 1000.0}) {
      const Scene scene = sceneOf(c, unit);
      const OrientationRepair& fix = scene.meshReports[0].orientation;
      const std::string repaired = fmt::format("{} faces, {} pieces turned", fix.reorientedTriangles,
                                               fix.piecesTurnedOutward);
      openvdb::FloatGrid::Ptr openVdb;
      double openVdbSeconds = 0.0;
      for (const SignMethodRow& m : kSignMethods) {
        control.checkStop();
        BakeOptions o;
        o.scene = c.name;
        o.method = m.method;
        o.resolution = res;
        o.frames = m.frames;
        o.device = s.device;
        o.pipeline.fineRes = res;
        o.pipeline.coarseRes = res / 2;
        o.pipeline.mode = m.mode;
        o.pipeline.rays = m.rays;
        // Three voxels: the grid spans the longest side E and a padding of the band on each side, so a band of
        // 3 (E + 2 band) / res voxels is 3 E / (res - 6).
        o.pipeline.band = 3.0 * positionBounds(scene.meshes[0]).maxExtent() / (res - 6);
        const BakeResult r = bake(scene, o);
        if (m.method == BakeMethod::OpenVdb) {
          openVdb = r.grid;
          openVdbSeconds = r.seconds;
        }
        const double h = r.spec.voxelSize;
        const FieldError e = compareWithFunction(
            *r.grid, [&](const openvdb::Vec3d& p) { return unit * c.solid(glm::dvec3(p.x(), p.y(), p.z()) / unit); },
            0.1 * h);
        const std::string vsOpenVdb =
            openVdb && m.method != BakeMethod::OpenVdb
                ? fmt::format("{:.3f}%", 100.0 * compareFields(*r.grid, *openVdb).signErrorRate())
                : "-";
        md += fmt::format("| {} | {:g} | {} | {} | {:.3f}% | {:.3f} / {:.2f} | {} | {:.2f} | {:.2f} |\n", c.name, unit,
                          repaired, m.name, 100.0 * e.signErrorRate(), e.meanAbs, e.maxAbs, vsOpenVdb, r.seconds,
                          r.seconds / openVdbSeconds);
        spdlog::info("sign suite: {} (unit {:g}), {}: {:.3f}% wrong signs", c.name, unit, m.name,
                     100.0 * e.signErrorRate());
        poll.done();
      }
    }
  return md;
}

} // namespace rtsdf::bench
