// The coarse-SDF passes on the GPU (lavapipe in CI) against their CPU references on real scenes: the same
// seeds and the same nearest seeds bit for bit (this is what proves the barriers between dispatches), and
// jump flooding against the exact distance transform of the same seeds.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "gpu/VulkanContext.h"
#include "sdf/CoarseReference.h"
#include "reference/ExactSdf.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/CoarseSdf.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>

using namespace rtsdf;
using gpu::shared::kNoSeed;

namespace {

/// One Vulkan context (validation on) for the whole suite; its error count must stay zero.
struct CoarseTag {
  static void releaseSuiteObjects();
};

class CoarseSdfGpu : public test::VulkanSuite<CoarseTag> {
protected:
  static CoarseSdfBuilder& builder() {
    if (!sBuilder) sBuilder = std::make_unique<CoarseSdfBuilder>(*sCtx);
    return *sBuilder;
  }

  /// GPU and CPU on the same triangles and grid: seeds and nearest seeds identical, distances within rounding.
  static void expectGpuEqualsCpu(const std::vector<glm::vec4>& corners, const GridSpec& spec, JfaVariant variant) {
    CoarseSdfSettings s;
    s.variant = variant;
    const CoarseSdf gpu = builder().build(corners, spec, s, true);
    const std::vector<std::uint32_t> seeds = voxelizeCpu(corners, spec);
    ASSERT_EQ(gpu.seeds.size(), seeds.size());
    std::size_t seedDiff = 0, seedCount = 0;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      seedDiff += gpu.seeds[i] != seeds[i];
      seedCount += seeds[i] != kNoSeed;
    }
    EXPECT_EQ(seedDiff, 0u) << "of " << seedCount << " seeds";
    const std::vector<std::uint32_t> nearest = jumpFloodCpu(seeds, spec.dims, variant);
    std::size_t nearestDiff = 0;
    for (std::size_t i = 0; i < nearest.size(); ++i) nearestDiff += gpu.nearest[i] != nearest[i];
    EXPECT_EQ(nearestDiff, 0u);
    const std::vector<float> dist =
        coarseDistanceCpu(nearest, spec.dims, float(spec.voxelSize), gpu.beta, emptySceneDistance(spec));
    for (std::size_t i = 0; i < dist.size(); ++i)
      ASSERT_NEAR(gpu.distance[i], dist[i], 1e-5f * (1.0f + std::fabs(dist[i]))) << i;
    EXPECT_GT(gpu.passTotal(JumpFloodPass::kName), 0.0);
  }

  static inline std::unique_ptr<CoarseSdfBuilder> sBuilder;
  friend struct CoarseTag;
};

void CoarseTag::releaseSuiteObjects() { CoarseSdfGpu::sBuilder.reset(); }

SceneGeometry sceneGeometry(const std::string& name) {
  return buildSceneGeometry(loadScene(test::dataPath("scenes/" + name)));
}

} // namespace

// At 128 the default scene's walls make long voxelization loops: an earlier voxelize.comp lost writes on
// lavapipe there (127 seeds; lavapipe stops loops after ~16k iterations) while passing at 64.
TEST_F(CoarseSdfGpu, DefaultSceneEqualsCpuForEveryVariant) {
  const SceneGeometry geo = sceneGeometry("default.json");
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, 128, 0.1);
  for (JfaVariant v : {JfaVariant::Jfa, JfaVariant::OnePlusJfa, JfaVariant::JfaPlusTwo}) {
    SCOPED_TRACE(toString(v));
    expectGpuEqualsCpu(triangleCorners(geo), spec, v);
  }
}

TEST_F(CoarseSdfGpu, BunnyEqualsCpuAt128) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  expectGpuEqualsCpu(triangleCorners(geo), GridSpec::fromBounds(geo.bounds, 128, 0.1), JfaVariant::OnePlusJfa);
}

TEST_F(CoarseSdfGpu, NonCubicThinEmptyAndBoundaryGrids) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  const auto corners = triangleCorners(geo);
  // 37 x 64 x 20: not cubic, not powers of two.
  GridSpec odd;
  odd.dims = {37, 64, 20};
  odd.voxelSize = geo.bounds.maxExtent() / 40.0;
  odd.origin = geo.bounds.center() - 0.5 * glm::dvec3(odd.dims) * odd.voxelSize;
  expectGpuEqualsCpu(corners, odd, JfaVariant::OnePlusJfa);
  // One voxel thick, through the middle of the bunny.
  GridSpec thin = odd;
  thin.dims = {48, 1, 48};
  thin.origin = geo.bounds.center() - 0.5 * glm::dvec3(thin.dims) * thin.voxelSize;
  expectGpuEqualsCpu(corners, thin, JfaVariant::JfaPlusTwo);
  // The mesh touches the grid's boundary (no padding).
  expectGpuEqualsCpu(corners, GridSpec::fromBounds(geo.bounds, 50, 0.0), JfaVariant::Jfa);
  // No triangles at all: no seeds anywhere, every voxel at the empty-scene distance.
  const CoarseSdf empty = builder().build(std::vector<glm::vec4>{}, odd, {}, true);
  for (std::size_t i = 0; i < empty.nearest.size(); ++i) {
    ASSERT_EQ(empty.seeds[i], kNoSeed);
    ASSERT_EQ(empty.nearest[i], kNoSeed);
    ASSERT_EQ(empty.distance[i], emptySceneDistance(odd));
  }
  // A single voxel.
  GridSpec one = odd;
  one.dims = {1, 1, 1};
  one.voxelSize = geo.bounds.maxExtent();
  one.origin = geo.bounds.center() - 0.5 * one.voxelSize;
  expectGpuEqualsCpu(corners, one, JfaVariant::OnePlusJfa);
}

TEST_F(CoarseSdfGpu, HugeTrianglesAreVoxelizedCompletely) {
  // Two triangles across a 300 x 300 x 3 grid: each covers ~270k voxels of range, far beyond what one shader
  // loop may run on lavapipe; VoxelizePass must split them into chunks and lose no seed.
  GridSpec spec;
  spec.dims = {300, 300, 3};
  spec.voxelSize = 1.0 / 300.0;
  spec.origin = glm::dvec3(0.0);
  const std::vector<glm::vec4> quad = {{0.01f, 0.01f, 0.004f, 1}, {0.99f, 0.01f, 0.006f, 1}, {0.99f, 0.99f, 0.005f, 1},
                                       {0.01f, 0.01f, 0.004f, 1}, {0.99f, 0.99f, 0.005f, 1}, {0.01f, 0.99f, 0.006f, 1}};
  expectGpuEqualsCpu(quad, spec, JfaVariant::OnePlusJfa);
}

TEST_F(CoarseSdfGpu, SeedsAreConservativeAndTight) {
  // A voxel is a seed exactly when a triangle touches its box: so every voxel holding a surface point is a
  // seed, and every seed's centre lies within half a voxel diagonal of the surface.
  const SceneGeometry geo = sceneGeometry("bunny.json");
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, 64, 0.1);
  const CoarseSdf c = builder().build(geo, spec, {}, true);
  const ExactDistanceField exact(geo);
  const float halfDiagonal = float(0.5 * std::sqrt(3.0) * spec.voxelSize);
  std::size_t seeds = 0;
  for (int z = 0; z < spec.dims.z; ++z)
    for (int y = 0; y < spec.dims.y; ++y)
      for (int x = 0; x < spec.dims.x; ++x) {
        if (c.seeds[spec.linear(x, y, z)] == kNoSeed) continue;
        ++seeds;
        const float d = std::fabs(exact.signedDistance(glm::vec3(spec.indexToWorld(glm::dvec3(x, y, z)))));
        ASSERT_LE(d, halfDiagonal * 1.0001f);
      }
  EXPECT_GT(seeds, 1000u);
  for (const WorldMesh& m : geo.meshes)
    for (const glm::uvec3& t : m.triangles) {
      const glm::dvec3 centroid = glm::dvec3(m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0;
      const glm::ivec3 v = glm::ivec3(glm::floor(spec.worldToIndex(centroid) + 0.5));
      ASSERT_NE(c.seeds[spec.linear(v.x, v.y, v.z)], kNoSeed);
    }
}

TEST(ExactEdt, MatchesBruteForce) {
  const glm::ivec3 dims(19, 7, 13);
  std::mt19937 rng(5);
  std::vector<std::uint32_t> seeds(std::size_t(dims.x) * dims.y * dims.z, kNoSeed);
  std::vector<glm::ivec3> points;
  for (int i = 0; i < 9; ++i) {
    const glm::ivec3 p(int(rng() % dims.x), int(rng() % dims.y), int(rng() % dims.z));
    seeds[(std::size_t(p.z) * dims.y + p.y) * dims.x + p.x] = gpu::shared::packSeed(p);
    points.push_back(p);
  }
  const std::vector<float> edt = exactEdtSquared(seeds, dims);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x) {
        int best = INT32_MAX;
        for (const auto& p : points) best = std::min(best, gpu::shared::distance2({x, y, z}, p));
        ASSERT_EQ(edt[(std::size_t(z) * dims.y + y) * dims.x + x], float(best));
      }
  const std::vector<std::uint32_t> none(seeds.size(), kNoSeed);
  for (float v : exactEdtSquared(none, dims)) ASSERT_TRUE(std::isinf(v));
}

TEST(JumpFlooding, ErrorsAgainstTheExactTransformStayWithinMeasuredBounds) {
  // Measured at 128 (voxels off / max error): bunny JFA 0.053% / 0.46, 1+JFA 0.062% / 0.36, JFA+2 0.0036% /
  // 0.15; default scene JFA 0.17% / 0.70, 1+JFA 0.0028% / 0.30, JFA+2 0.093% / 0.67. Bounds: 1+JFA and
  // JFA+2 off on at most 0.2% of voxels by at most one voxel, and JFA+2 never worse than plain JFA.
  for (const char* scene : {"bunny.json", "default.json"}) {
    const SceneGeometry geo = sceneGeometry(scene);
    const GridSpec spec = GridSpec::fromBounds(geo.bounds, 128, 0.1);
    const auto seeds = voxelizeCpu(triangleCorners(geo), spec);
    const auto exact = exactEdtSquared(seeds, spec.dims);
    JfaAccuracy acc[3];
    int i = 0;
    for (JfaVariant v : {JfaVariant::Jfa, JfaVariant::OnePlusJfa, JfaVariant::JfaPlusTwo}) {
      acc[i] = compareWithExact(jumpFloodCpu(seeds, spec.dims, v), exact, spec.dims);
      std::printf("%s at 128, %-6s: %.4f%% of voxels off, max %.3f voxels\n", scene, toString(v),
                  100.0 * acc[i].wrongFraction(), acc[i].maxError);
      ++i;
    }
    EXPECT_LE(acc[1].wrongFraction(), 2e-3);
    EXPECT_LE(acc[1].maxError, 1.0);
    EXPECT_LE(acc[2].wrongFraction(), 2e-3);
    EXPECT_LE(acc[2].maxError, 1.0);
    EXPECT_LE(acc[2].wrongFraction(), acc[0].wrongFraction());
  }
}
