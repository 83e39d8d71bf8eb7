// Micro-benchmarks of the exact reference's kernels.
#include "reference/TriangleDistance.h"
#include "reference/WindingNumber.h"
#include "scene/Mesh.h"

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

} // namespace

BENCHMARK_MAIN();
