// Micro-benchmarks of the exact reference's kernels, and its band fill on an open scan against OpenVDB's
// meshToLevelSet on the same voxels (the anchor, measured in the same run).
#include "reference/ExactSdf.h"
#include "reference/OpenVdbLevelSet.h"
#include "reference/TriangleDistance.h"
#include "reference/WindingNumber.h"
#include "scene/Mesh.h"
#include "scene/ScanMeshes.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <benchmark/benchmark.h>

#include <random>

namespace {

void BM_PointTriangleDistance(benchmark::State& state) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> pts(1024);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0.2f);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rtsdf::distanceSquaredToTriangle(pts[i++ & 1023], a, b, c));
  }
}
BENCHMARK(BM_PointTriangleDistance);

void BM_WindingNumberBox(benchmark::State& state) {
  const rtsdf::Mesh box = rtsdf::makeBoxMesh({1, 1, 1});
  const rtsdf::WindingNumberTree tree(box.positions, box.triangles);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto _ : state) benchmark::DoNotOptimize(tree.evaluate({u(rng), u(rng), u(rng)}));
}
BENCHMARK(BM_WindingNumberBox);

/// The open scans of `rtsdf bench --suite reference` on the grid of resolution state.range(1) with a band of 3 voxels,
/// by state.range(0): 0 the bunny split in four 3 times (235k triangles) with 12 holes cut (one piece); 1 the
/// icosphere split 7 times (328k triangles) cut into eight separated patches; 2 the bunny split 3 times as a scan in
/// pieces (two halves, a non-manifold fin, six floating fragments, 12 holes).
struct OpenScan {
  rtsdf::Scene scene;
  rtsdf::SceneGeometry geometry;
  rtsdf::GridSpec spec;
  double band = 0.0;
  OpenScan(int kind, int res) {
    scene = rtsdf::loadScene(std::string(RTSDF_DATA_DIR) + "/meshes/bunny.obj");
    const double extent = rtsdf::buildSceneGeometry(scene, 0.0).bounds.maxExtent();
    const rtsdf::Mesh fine = rtsdf::subdivideMesh(scene.meshes[0], 3);
    if (kind == 0) scene.meshes[0] = rtsdf::cutHoles(fine, 12, float(0.03 * extent));
    if (kind == 1) scene.meshes[0] = rtsdf::makeSphereInPatches(7, 0.01f);
    if (kind == 2) scene.meshes[0] = rtsdf::makeScanInPieces(fine, 12);
    scene.meshReports[0] = rtsdf::validateMesh(scene.meshes[0]);
    geometry = rtsdf::buildSceneGeometry(scene, 0.0);
    band = 3.0 * geometry.bounds.maxExtent() / res;
    spec = rtsdf::GridSpec::fromBounds(geometry.bounds, res, band);
  }
};

void BM_ExactOpenScan(benchmark::State& state) {
  const OpenScan scan(int(state.range(0)), int(state.range(1)));
  rtsdf::ExactSdfOptions opt;
  opt.band = scan.band;
  opt.progress = false;
  rtsdf::ExactSdfStats stats;
  for (auto _ : state) benchmark::DoNotOptimize(rtsdf::exactSignedDistance(scan.geometry, scan.spec, opt, &stats));
  state.counters["winding_share"] =
      double(stats.windingQueries) / double(std::max<std::uint64_t>(1, stats.activeVoxels));
}
BENCHMARK(BM_ExactOpenScan)->ArgsProduct({{0, 1, 2}, {256}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_OpenVdbOpenScan(benchmark::State& state) {
  const OpenScan scan(int(state.range(0)), int(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(rtsdf::openvdbLevelSet(scan.geometry, scan.spec, scan.band));
}
BENCHMARK(BM_OpenVdbOpenScan)->ArgsProduct({{0, 1, 2}, {256}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

} // namespace

BENCHMARK_MAIN();
