// The coarse-SDF passes on the GPU (lavapipe in CI) against their CPU references on real scenes: the same
// seeds and the same nearest seeds bit for bit (this is what proves the barriers between dispatches), and
// jump flooding against the exact distance transform of the same seeds.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "gpu/VulkanContext.h"
#include "sdf/coarse/CoarseCpu.h"
#include "reference/ExactSdf.h"
#include "reference/TriangleDistance.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/coarse/CoarseScroll.h"
#include "sdf/coarse/CoarseSdf.h"
#include "sdf/refine/RefineCpu.h"
#include "sdf/refine/RefinePasses.h"
#include "sdf/scenebvh/GpuSceneBvh.h"
#include "util/Error.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cstring>
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
  static void expectGpuEqualsCpu(const std::vector<glm::vec4>& corners, const GridSpec& spec, CoarseMethod method,
                                 std::uint32_t maxChunkGroups = gpu::shared::kVoxelizeMaxChunkGroups,
                                 std::uint32_t chunkVoxels = 0) {
    CoarseSdfSettings s;
    s.method = method;
    s.maxChunkGroups = maxChunkGroups;
    s.chunkVoxels = chunkVoxels;
    const CoarseSdf gpu = builder().build(corners, spec, s, true);
    const std::vector<std::uint32_t> seeds = voxelizeCpu(corners, spec);
    ASSERT_EQ(gpu.seeds.size(), seeds.size());
    std::size_t seedDiff = 0, seedCount = 0;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      seedDiff += gpu.seeds[i] != seeds[i];
      seedCount += seeds[i] != kNoSeed;
    }
    EXPECT_EQ(seedDiff, 0u) << "of " << seedCount << " seeds";
    const std::vector<std::uint32_t> nearest = nearestSeedsCpu(seeds, spec.dims, method);
    std::size_t nearestDiff = 0;
    for (std::size_t i = 0; i < nearest.size(); ++i) nearestDiff += gpu.nearest[i] != nearest[i];
    EXPECT_EQ(nearestDiff, 0u);
    const std::vector<float> dist =
        coarseDistanceCpu(nearest, spec.dims, float(spec.voxelSize), gpu.beta, emptySceneDistance(spec));
    for (std::size_t i = 0; i < dist.size(); ++i)
      ASSERT_NEAR(gpu.distance[i], dist[i], 1e-5f * (1.0f + std::fabs(dist[i]))) << i;
    EXPECT_GT(gpu.passTotal(isJumpFlooding(method) ? JumpFloodPass::kName : ExactEdtPass::kName), 0.0);
  }

  /// The triangles VoxelizePass lists for its second dispatch with @a chunkVoxels per invocation, and how many the
  /// CPU counts: those whose voxel range (the shared voxelRangeChunks) needs more than kVoxelizeFirstChunks.
  static std::pair<std::uint32_t, std::uint32_t> largeTriangles(const std::vector<glm::vec4>& corners,
                                                                const GridSpec& spec, std::uint32_t chunkVoxels) {
    CoarseSdfSettings s;
    s.chunkVoxels = chunkVoxels;
    const std::uint32_t gpuCount = builder().build(corners, spec, s, true).largeTriangles;
    const gpu::shared::VoxelizeParams p = voxelizeParams(spec, std::uint32_t(corners.size() / 3));
    std::uint32_t cpuCount = 0;
    for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
      auto place = [&](std::size_t i) { return gpu::shared::toVoxelSpace(glm::vec3(corners[i]), p.originInvH); };
      cpuCount += gpu::shared::voxelRangeChunks(place(t), place(t + 1), place(t + 2), glm::ivec3(p.clipLo),
                                                   glm::ivec3(p.clipHi), chunkVoxels) >
                  gpu::shared::kVoxelizeFirstChunks;
    }
    return {gpuCount, cpuCount};
  }

  /// ExactEdtPass alone on given seeds: its nearest seeds.
  static std::vector<std::uint32_t> exactEdtGpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims) {
    const ExactEdtPass pass(*sCtx);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    gpu::Buffer a, b, region;
    gpu::reserveAndUpload(*sCtx, a, seeds.data(), seeds.size() * 4, usage, "seeds");
    gpu::reserve(*sCtx, b, seeds.size() * 4, usage, gpu::Buffer::Memory::Device, "scratch");
    gpu::reserve(*sCtx, region, sizeof(gpu::shared::CoarseRegion), usage, gpu::Buffer::Memory::Device, "region");
    gpu::CommandBuffer cmd(*sCtx);
    pass.execute(cmd.handle(), nullptr, {a, region, region}, {b}, {dims});
    cmd.submitAndWait();
    std::vector<std::uint32_t> out(seeds.size());
    gpu::download(*sCtx, b, out.data(), out.size() * 4);
    return out;
  }

  /// What a build over a change computes from its passes alone: ExactEdtPass (kept) and CoarseDistancePass over
  /// @a before, then CoarseRegionPass with @a change, ExactEdtPass and CoarseDistancePass over what @a after changed
  /// in it. Also returns the block bounds and distances the first build left, the region, and the second build's
  /// changed-block marks.
  struct OverChange {
    std::vector<std::uint32_t> nearest, blockMaxBefore, changedBlocks;
    std::vector<float> distance, distanceBefore;
    gpu::shared::CoarseRegion region{};
    std::vector<std::uint32_t> blocks, columns; ///< the region's lists, ascending
  };
  static OverChange buildOverChange(const std::vector<std::uint32_t>& before, const std::vector<std::uint32_t>& after,
                                    const glm::ivec3& dims, const CoarseVoxelBox& change) {
    const ExactEdtPass edt(*sCtx);
    const CoarseRegionPass regionPass(*sCtx);
    const CoarseDistancePass distancePass(*sCtx);
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    const std::size_t bytes = before.size() * 4;
    const glm::uvec3 bd(gpu::shared::coarseBlockDims(dims));
    const std::size_t blocks = std::size_t(bd.x) * bd.y * bd.z;
    gpu::Buffer seeds, scratch, planes, nearest, distance, changed, blockMax, region, lists, marks;
    gpu::reserveAndUpload(*sCtx, seeds, before.data(), bytes, usage, "seeds");
    for (gpu::Buffer* b : {&scratch, &planes, &nearest, &distance})
      gpu::reserve(*sCtx, *b, bytes, usage, gpu::Buffer::Memory::Device, "transform");
    gpu::reserve(*sCtx, changed, sizeof(gpu::shared::ChangedBox), usage, gpu::Buffer::Memory::Device, "changed");
    gpu::reserve(*sCtx, blockMax, blocks * 4, usage, gpu::Buffer::Memory::Device, "block bounds");
    gpu::reserve(*sCtx, marks, blocks * 4, usage, gpu::Buffer::Memory::Device, "changed blocks");
    gpu::reserve(*sCtx, region, sizeof(gpu::shared::CoarseRegion), usage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                 gpu::Buffer::Memory::Device, "region");
    const std::size_t listWords = gpu::shared::coarseRegionListWords(dims);
    gpu::reserve(*sCtx, lists, listWords * 4, usage, gpu::Buffer::Memory::Device, "region lists");
    gpu::shared::CoarseDistanceParams dp{};
    dp.dims = glm::ivec4(dims, 0);
    dp.voxelSize = 0.5f;
    dp.beta = 0.25f;
    dp.emptyDistance = 99.0f;
    dp.flags = gpu::shared::kCoarseDistanceKeepBounds;
    {
      gpu::CommandBuffer cmd(*sCtx);
      vkCmdFillBuffer(cmd.handle(), blockMax.handle(), 0, VK_WHOLE_SIZE, 0u);
      vkCmdFillBuffer(cmd.handle(), changed.handle(), 0, VK_WHOLE_SIZE, 0u);
      vkCmdFillBuffer(cmd.handle(), marks.handle(), 0, VK_WHOLE_SIZE, 0u);
      vkCmdFillBuffer(cmd.handle(), distance.handle(), 0, VK_WHOLE_SIZE, 0u);
      gpu::computeBarrier(cmd.handle());
      edt.execute(cmd.handle(), nullptr, {seeds, region, lists}, {scratch, &planes, &nearest}, {dims});
      distancePass.execute(cmd.handle(), nullptr, {nearest, region, lists}, {distance, changed, blockMax, marks}, dp);
      cmd.submitAndWait();
    }
    OverChange out;
    out.blockMaxBefore.resize(blocks);
    gpu::download(*sCtx, blockMax, out.blockMaxBefore.data(), blocks * 4);
    out.distanceBefore.resize(before.size());
    gpu::download(*sCtx, distance, out.distanceBefore.data(), bytes);
    upload(*sCtx, seeds, after.data(), bytes);
    {
      gpu::CommandBuffer cmd(*sCtx);
      vkCmdFillBuffer(cmd.handle(), marks.handle(), 0, VK_WHOLE_SIZE, 0u);
      gpu::computeBarrier(cmd.handle());
      const std::vector<CoarseVoxelBox> changes{change};
      regionPass.execute(cmd.handle(), nullptr, {blockMax}, {region, lists}, {dims, changes});
      edt.execute(cmd.handle(), nullptr, {seeds, region, lists}, {scratch, &planes, &nearest}, {dims, &changes});
      dp.flags = gpu::shared::kCoarseDistanceRegionOnly | gpu::shared::kCoarseDistanceKeepBounds;
      distancePass.execute(cmd.handle(), nullptr, {nearest, region, lists}, {distance, changed, blockMax, marks}, dp);
      cmd.submitAndWait();
    }
    out.nearest.resize(before.size());
    out.distance.resize(before.size());
    gpu::download(*sCtx, nearest, out.nearest.data(), bytes);
    gpu::download(*sCtx, distance, out.distance.data(), bytes);
    gpu::download(*sCtx, region, &out.region, sizeof(out.region));
    out.changedBlocks.resize(blocks);
    gpu::download(*sCtx, marks, out.changedBlocks.data(), blocks * 4);
    std::vector<std::uint32_t> words(listWords);
    gpu::download(*sCtx, lists, words.data(), listWords * 4);
    const auto columnsAt = std::ptrdiff_t(gpu::shared::coarseRegionColumnsAt(dims));
    const auto blocksAt = std::ptrdiff_t(gpu::shared::coarseRegionBlocksAt(dims));
    EXPECT_EQ(words[0], out.region.counts.x) << "the host's copy of the counts";
    EXPECT_EQ(words[1], out.region.counts.y);
    EXPECT_EQ(words[2], out.region.counts.z);
    out.columns.assign(words.begin() + columnsAt, words.begin() + columnsAt + std::ptrdiff_t(out.region.counts.y));
    out.blocks.assign(words.begin() + blocksAt, words.begin() + blocksAt + std::ptrdiff_t(out.region.counts.x));
    std::sort(out.columns.begin(), out.columns.end());
    std::sort(out.blocks.begin(), out.blocks.end());
    return out;
  }

  /// A build over a change left @a nearest (found apart from it) and the CPU copy's distances of them, bit for bit,
  /// with buildOverChange's distance parameters.
  static void expectNearestAndDistances(const OverChange& gpu, const std::vector<std::uint32_t>& nearest,
                                        const glm::ivec3& dims) {
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < nearest.size(); ++i) wrong += gpu.nearest[i] != nearest[i];
    EXPECT_EQ(wrong, 0u) << "voxels whose nearest seed is not the one found apart";
    const std::vector<float> cpu = coarseDistanceCpu(nearest, dims, 0.5f, 0.25f, 99.0f);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) differ += std::memcmp(&cpu[i], &gpu.distance[i], 4) != 0;
    EXPECT_EQ(differ, 0u) << "distances not those of the CPU copy";
  }

  static inline std::unique_ptr<CoarseSdfBuilder> sBuilder;
  friend struct CoarseTag;
};

void CoarseTag::releaseSuiteObjects() { CoarseSdfGpu::sBuilder.reset(); }

SceneGeometry sceneGeometry(const std::string& name) {
  return buildSceneGeometry(loadScene(test::dataPath("scenes/" + name)));
}

/// Brute force: each voxel's squared distance (in voxels) to the nearest of @a seeds, trying every seed.
std::vector<int> bruteForceEdtSquared(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims) {
  std::vector<glm::ivec3> points;
  for (std::uint32_t s : seeds)
    if (s != kNoSeed) points.push_back(gpu::shared::unpackSeed(s));
  std::vector<int> out(seeds.size(), INT32_MAX);
  tbb::parallel_for(std::size_t(0), seeds.size(), [&](std::size_t i) {
    const glm::ivec3 p(int(i % dims.x), int((i / dims.x) % dims.y), int(i / (std::size_t(dims.x) * dims.y)));
    int best = INT32_MAX;
    for (const glm::ivec3& q : points) best = std::min(best, gpu::shared::distance2(p, q));
    out[i] = best;
  });
  return out;
}

/// Brute force: the unsigned distance from @a p to the nearest triangle of @a geo, trying every triangle.
float bruteForceSurfaceDistance(const SceneGeometry& geo, const glm::vec3& p) {
  float best = std::numeric_limits<float>::infinity();
  for (const WorldMesh& m : geo.meshes)
    for (const glm::uvec3& t : m.triangles)
      best = std::min(best, distanceSquaredToTriangle(p, m.positions[t.x], m.positions[t.y], m.positions[t.z]));
  return std::sqrt(best);
}

} // namespace

// Plain jump flooding on the GPU against a brute-force exact transform (every voxel tries every seed) of the same
// seeds, on the bunny voxelized at 48. Measured (lavapipe; the passes are deterministic): 0.0985% of voxels off,
// max error 0.434 voxels. Bounds: the measured values plus a small margin (0.11%, 0.5 voxels).
TEST_F(CoarseSdfGpu, PlainJumpFloodingIsWithinItsBoundOfABruteForceTransform) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, 48, 0.1);
  CoarseSdfSettings s;
  s.method = CoarseMethod::Jfa;
  const CoarseSdf jfa = builder().build(geo, spec, s, true);
  const std::vector<int> exact = bruteForceEdtSquared(jfa.seeds, spec.dims);
  std::size_t off = 0, seeds = 0;
  double maxError = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    seeds += jfa.seeds[i] != kNoSeed;
    ASSERT_NE(jfa.nearest[i], kNoSeed) << i;
    const glm::ivec3 p(int(i % spec.dims.x), int((i / spec.dims.x) % spec.dims.y),
                       int(i / (std::size_t(spec.dims.x) * spec.dims.y)));
    const int found = gpu::shared::distance2(p, gpu::shared::unpackSeed(jfa.nearest[i]));
    ASSERT_GE(found, exact[i]) << "a nearer seed than the nearest at voxel " << i;
    if (found == exact[i]) continue;
    ++off;
    maxError = std::max(maxError, std::sqrt(double(found)) - std::sqrt(double(exact[i])));
  }
  const double fraction = double(off) / double(exact.size());
  std::printf("bunny at 48, plain JFA against brute force: %zu seeds, %.4f%% of voxels off, max %.3f voxels\n", seeds,
              100.0 * fraction, maxError);
  EXPECT_GT(seeds, 1000u);
  EXPECT_LE(fraction, 1.1e-3);
  EXPECT_LE(maxError, 0.5);
}

// CoarseDistancePass value by value against an independent computation: with the exact transform and seeds at
// the voxels whose boxes a triangle touches, c + beta at every voxel is within half a voxel diagonal of the
// distance to the nearest triangle found by trying every triangle (bunny at 40, every voxel).
TEST_F(CoarseSdfGpu, CoarseDistancesAreWithinHalfAVoxelDiagonalOfTheBruteForceSurfaceDistance) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, 40, 0.1);
  CoarseSdfSettings s;
  s.method = CoarseMethod::Edt;
  const CoarseSdf c = builder().build(geo, spec, s);
  ASSERT_EQ(c.distance.size(), std::size_t(spec.dims.x) * spec.dims.y * spec.dims.z);
  EXPECT_NEAR(c.beta, 0.5 * spec.voxelSize, 1e-6 * spec.voxelSize) << "the default beta is half a voxel";
  std::vector<float> truth(c.distance.size());
  tbb::parallel_for(std::size_t(0), truth.size(), [&](std::size_t i) {
    const glm::dvec3 ijk(double(i % spec.dims.x), double((i / spec.dims.x) % spec.dims.y),
                         double(i / (std::size_t(spec.dims.x) * spec.dims.y)));
    truth[i] = bruteForceSurfaceDistance(geo, glm::vec3(spec.indexToWorld(ijk)));
  });
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * spec.voxelSize;
  double maxDiff = 0.0, sumDiff = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const double diff = std::fabs(double(c.distance[i]) + c.beta - truth[i]);
    ASSERT_LE(diff, halfDiagonal * 1.0001) << "voxel " << i << ": coarse " << c.distance[i] << ", surface "
                                           << truth[i];
    maxDiff = std::max(maxDiff, diff);
    sumDiff += diff;
  }
  std::printf("bunny at 40: |c + beta - distance| mean %.4f, max %.4f voxels (bound %.4f)\n",
              sumDiff / truth.size() / spec.voxelSize, maxDiff / spec.voxelSize, halfDiagonal / spec.voxelSize);
}

// At 128 the default scene's walls make long voxelization loops: an earlier voxelize.comp lost writes on
// lavapipe there (127 seeds; lavapipe stops loops after ~16k iterations) while passing at 64.
TEST_F(CoarseSdfGpu, DefaultSceneEqualsCpuForEveryVariant) {
  const SceneGeometry geo = sceneGeometry("default.json");
  const GridSpec spec = GridSpec::fromBounds(geo.bounds, 128, 0.1);
  for (CoarseMethod v : {CoarseMethod::Edt, CoarseMethod::Jfa, CoarseMethod::OnePlusJfa, CoarseMethod::JfaPlusTwo}) {
    SCOPED_TRACE(toString(v));
    expectGpuEqualsCpu(triangleCorners(geo), spec, v);
  }
  // A GPU's chunks (CI runs lavapipe, a CPU device, whose default is longer chunks). Then the room's floor and walls
  // take VoxelizePass's second dispatch and the teapot's triangles only its first: both must lose no seed.
  SCOPED_TRACE("GPU chunks");
  expectGpuEqualsCpu(triangleCorners(geo), spec, CoarseMethod::Edt, gpu::shared::kVoxelizeMaxChunkGroups,
                     gpu::shared::kVoxelizeChunkVoxelsGpu);
  const auto [listed, listedCpu] = largeTriangles(triangleCorners(geo), spec, gpu::shared::kVoxelizeChunkVoxelsGpu);
  EXPECT_EQ(listed, listedCpu);
  EXPECT_GT(listed, 0u);
  EXPECT_LT(listed, geo.triangleCount() / 10);
}

TEST_F(CoarseSdfGpu, BunnyEqualsCpuAt128) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  for (CoarseMethod v : {CoarseMethod::Edt, CoarseMethod::OnePlusJfa}) {
    SCOPED_TRACE(toString(v));
    expectGpuEqualsCpu(triangleCorners(geo), GridSpec::fromBounds(geo.bounds, 128, 0.1), v);
  }
}

// The exact transform's distances are the Felzenszwalb-Huttenlocher transform's, bit for bit, on real scenes
// at the paper's coarse size, on the GPU (through the whole builder) and the CPU.
TEST_F(CoarseSdfGpu, ExactEdtDistancesEqualTheExactTransform) {
  for (const char* scene : {"default.json", "bunny.json"}) {
    SCOPED_TRACE(scene);
    const SceneGeometry geo = sceneGeometry(scene);
    const GridSpec spec = GridSpec::fromBounds(geo.bounds, 128, 0.1);
    CoarseSdfSettings s;
    s.method = CoarseMethod::Edt;
    const CoarseSdf gpu = builder().build(geo, spec, s, true);
    const std::vector<float> exact = exactEdtSquared(gpu.seeds, spec.dims);
    const JfaAccuracy acc = compareWithExact(gpu.nearest, exact, spec.dims);
    EXPECT_GT(acc.voxels, 0u);
    EXPECT_EQ(acc.wrong, 0u);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const glm::ivec3 p(int(i % spec.dims.x), int((i / spec.dims.x) % spec.dims.y),
                         int(i / (std::size_t(spec.dims.x) * spec.dims.y)));
      differ += gpu.nearest[i] == kNoSeed || float(gpu::shared::distance2(p, gpu::shared::unpackSeed(gpu.nearest[i]))) != exact[i];
    }
    EXPECT_EQ(differ, 0u);
  }
}

// Random seeds, dense enough for many ties, on grids with lines up to kMaxSeedAxis long (lavapipe stops shader
// loops after ~16k iterations: the line loops must stay well below): GPU == CPU reference == brute force,
// including the tie rule (the smallest packed seed among the nearest).
TEST_F(CoarseSdfGpu, ExactEdtEqualsBruteForceWithTiesAndLongLines) {
  std::mt19937 rng(11);
  for (const glm::ivec3 dims : {glm::ivec3(23, 17, 31), glm::ivec3(1024, 3, 2), glm::ivec3(2, 1024, 3),
                                glm::ivec3(3, 2, 1024), glm::ivec3(1, 1, 1), glm::ivec3(9, 1, 1)}) {
    SCOPED_TRACE(::testing::Message() << dims.x << "x" << dims.y << "x" << dims.z);
    const std::size_t n = std::size_t(dims.x) * dims.y * dims.z;
    std::vector<std::uint32_t> seeds(n, kNoSeed);
    std::vector<std::uint32_t> points;
    for (std::size_t i = 0; i < std::max<std::size_t>(1, n / 60); ++i) {
      const glm::ivec3 p(int(rng() % dims.x), int(rng() % dims.y), int(rng() % dims.z));
      seeds[(std::size_t(p.z) * dims.y + p.y) * dims.x + p.x] = gpu::shared::packSeed(p);
      points.push_back(gpu::shared::packSeed(p));
    }
    const std::vector<std::uint32_t> cpu = exactEdtNearestCpu(seeds, dims);
    EXPECT_EQ(exactEdtGpu(seeds, dims), cpu);
    for (std::size_t i = 0; i < n; ++i) {
      const glm::ivec3 q(int(i % dims.x), int((i / dims.x) % dims.y), int(i / (std::size_t(dims.x) * dims.y)));
      std::uint32_t best = kNoSeed;
      for (std::uint32_t p : points) best = gpu::shared::nearerSeed(q, best, p);
      ASSERT_EQ(cpu[i], best) << "voxel " << q.x << "," << q.y << "," << q.z;
    }
    const std::vector<std::uint32_t> none(n, kNoSeed);
    EXPECT_EQ(exactEdtGpu(none, dims), none);
  }
}

// A build over a change: random seeds, then those inside a box drawn again (some boxes emptied, one at a corner, an
// empty scene gaining seeds and one losing them all). ExactEdtPass and CoarseDistancePass over the planes the box
// crosses and the region CoarseRegionPass gives (equal to its CPU copy) leave the nearest seeds of a brute-force
// search over the new seeds (the tie rule too) and the distances bit for bit of the CPU copy on them; the region is
// less than the grid where the seeds are dense.
TEST_F(CoarseSdfGpu, ExactEdtOverAChangeEqualsBruteForce) {
  std::mt19937 rng(5);
  const glm::ivec3 dims(37, 29, 33);
  const std::size_t n = std::size_t(dims.x) * dims.y * dims.z;
  auto index = [&](const glm::ivec3& p) { return (std::size_t(p.z) * dims.y + p.y) * dims.x + p.x; };
  auto scatter = [&](std::vector<std::uint32_t>& seeds, const CoarseVoxelBox& box, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
      const glm::ivec3 e = box.hi - box.lo + 1;
      const glm::ivec3 p = box.lo + glm::ivec3(int(rng() % e.x), int(rng() % e.y), int(rng() % e.z));
      seeds[index(p)] = gpu::shared::packSeed(p);
    }
  };
  const CoarseVoxelBox grid{glm::ivec3(0), dims - 1};
  struct Case {
    const char* name;
    std::size_t seedsBefore, seedsInBox;
    CoarseVoxelBox box;
  };
  const std::vector<Case> cases = {{"dense, a middle box", n / 40, 30, {{10, 8, 12}, {18, 14, 17}}},
                                   {"dense, a box emptied", n / 40, 0, {{3, 20, 5}, {12, 28, 9}}},
                                   {"dense, a corner box", n / 40, 5, {{33, 25, 29}, {36, 28, 32}}},
                                   {"sparse, a middle box", 12, 3, {{15, 10, 10}, {20, 16, 14}}},
                                   {"empty before", 0, 4, {{4, 4, 4}, {9, 8, 7}}},
                                   {"every seed removed", 0, 0, {{4, 4, 4}, {9, 8, 7}}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<std::uint32_t> before(n, kNoSeed);
    scatter(before, grid, c.seedsBefore);
    if (std::string(c.name) == "every seed removed") scatter(before, c.box, 6);
    std::vector<std::uint32_t> after = before;
    for (int z = c.box.lo.z; z <= c.box.hi.z; ++z)
      for (int y = c.box.lo.y; y <= c.box.hi.y; ++y)
        for (int x = c.box.lo.x; x <= c.box.hi.x; ++x) after[index({x, y, z})] = kNoSeed;
    scatter(after, c.box, c.seedsInBox);
    const OverChange gpu = buildOverChange(before, after, dims, c.box);
    std::vector<std::uint32_t> brute(n, kNoSeed);
    std::vector<std::uint32_t> points;
    for (std::uint32_t s : after)
      if (s != kNoSeed) points.push_back(s);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
      const glm::ivec3 q(int(i % dims.x), int((i / dims.x) % dims.y), int(i / (std::size_t(dims.x) * dims.y)));
      for (std::uint32_t p : points) brute[i] = gpu::shared::nearerSeed(q, brute[i], p);
    });
    expectNearestAndDistances(gpu, brute, dims);
    const CoarseRegionLists cpuRegion = coarseRegionCpu(gpu.blockMaxBefore, dims, c.box);
    EXPECT_EQ(gpu.blocks, cpuRegion.blocks);
    EXPECT_EQ(gpu.columns, cpuRegion.columns);
    EXPECT_EQ(gpu.region.counts.z, cpuRegion.voxels);
    // The blocks whose voxels changed, marked with the neighbours they reach: the CPU copy's on the two fields.
    EXPECT_EQ(gpu.changedBlocks, changedBlockMarksCpu(gpu.distanceBefore, gpu.distance, dims));
    const std::uint64_t covered = gpu.region.counts.z;
    std::printf("%s: region %llu of %zu voxels\n", c.name, static_cast<unsigned long long>(covered), n);
    if (c.seedsBefore >= n / 40) EXPECT_LT(covered, n / 2) << "dense seeds: the change reaches a part of the grid";
  }
  // A build over a change without the kept transform, or with more boxes than the region takes, is refused before
  // anything is recorded. (A box may lie beyond the grid: the seeds a scroll took out of it.)
  const ExactEdtPass edt(*sCtx);
  const CoarseRegionPass regionPass(*sCtx);
  gpu::Buffer buf;
  gpu::reserve(*sCtx, buf, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "unused");
  const std::vector<CoarseVoxelBox> outside{{{0, 0, -1}, {3, 3, 3}}};
  gpu::CommandBuffer cmd(*sCtx);
  EXPECT_THROW(edt.execute(cmd.handle(), nullptr, {buf, buf, buf}, {buf}, {dims, &outside}), Error);
  EXPECT_THROW(regionPass.execute(cmd.handle(), nullptr, {buf}, {buf, buf},
                                  {dims, std::vector<CoarseVoxelBox>(RTSDF_COARSE_MAX_CHANGES + 1, outside[0])}),
               Error);
}

// A build over a change whose region lists more blocks than one row of CoarseDistancePass's groups holds
// (kCoarseRegionGroupsX groups of RTSDF_COARSE_REGION_BLOCKS_PER_GROUP blocks): an empty grid gaining seeds reaches
// every block, and every voxel's nearest seed and distance are the CPU copy's.
TEST_F(CoarseSdfGpu, ABuildOverAChangeListingMoreBlocksThanARowOfGroupsEqualsTheCpuCopy) {
  const glm::ivec3 dims(1024, 64, 68);
  const glm::ivec3 bd = gpu::shared::coarseBlockDims(dims);
  const std::size_t blocks = std::size_t(bd.x) * bd.y * bd.z;
  ASSERT_GT(blocks, std::size_t(gpu::shared::kCoarseRegionGroupsX) * RTSDF_COARSE_REGION_BLOCKS_PER_GROUP);
  const std::size_t n = std::size_t(dims.x) * dims.y * dims.z;
  std::vector<std::uint32_t> before(n, kNoSeed), after(n, kNoSeed);
  const CoarseVoxelBox box{{500, 30, 30}, {510, 36, 40}};
  std::mt19937 rng(3);
  for (int i = 0; i < 20; ++i) {
    const glm::ivec3 p = box.lo + glm::ivec3(int(rng() % 11), int(rng() % 7), int(rng() % 11));
    after[(std::size_t(p.z) * dims.y + p.y) * dims.x + p.x] = gpu::shared::packSeed(p);
  }
  const OverChange gpu = buildOverChange(before, after, dims, box);
  EXPECT_EQ(gpu.region.counts.x, blocks) << "an empty grid: every block is reached";
  EXPECT_EQ(gpu.region.counts.y, std::uint32_t(bd.x * bd.y));
  EXPECT_EQ(gpu.region.counts.z, n);
  EXPECT_GT(gpu.region.distanceGroups.y, 1u) << "the groups fill more than one row";
  expectNearestAndDistances(gpu, exactEdtNearestCpu(after, dims), dims);
}

TEST_F(CoarseSdfGpu, NonCubicThinEmptyAndBoundaryGrids) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  const auto corners = triangleCorners(geo);
  // 37 x 64 x 20: not cubic, not powers of two.
  GridSpec odd;
  odd.dims = {37, 64, 20};
  odd.voxelSize = geo.bounds.maxExtent() / 40.0;
  odd.origin = geo.bounds.center() - 0.5 * glm::dvec3(odd.dims) * odd.voxelSize;
  expectGpuEqualsCpu(corners, odd, CoarseMethod::OnePlusJfa);
  expectGpuEqualsCpu(corners, odd, CoarseMethod::Edt);
  // One voxel thick, through the middle of the bunny.
  GridSpec thin = odd;
  thin.dims = {48, 1, 48};
  thin.origin = geo.bounds.center() - 0.5 * glm::dvec3(thin.dims) * thin.voxelSize;
  expectGpuEqualsCpu(corners, thin, CoarseMethod::JfaPlusTwo);
  expectGpuEqualsCpu(corners, thin, CoarseMethod::Edt);
  // The mesh touches the grid's boundary (no padding).
  expectGpuEqualsCpu(corners, GridSpec::fromBounds(geo.bounds, 50, 0.0), CoarseMethod::Jfa);
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
  expectGpuEqualsCpu(corners, one, CoarseMethod::OnePlusJfa);
  expectGpuEqualsCpu(corners, one, CoarseMethod::Edt);
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
  expectGpuEqualsCpu(quad, spec, CoarseMethod::OnePlusJfa);
  expectGpuEqualsCpu(quad, spec, CoarseMethod::Edt);
  // More chunks (66) than work groups along y (as a range of more than kVoxelizeMaxChunkGroups chunks would have
  // on a larger grid): the chunks go in layers along z (an earlier version that strided through them in one
  // invocation lost a third of these seeds on lavapipe).
  expectGpuEqualsCpu(quad, spec, CoarseMethod::Edt, gpu::shared::kVoxelizeMinChunkGroups);
  // The shortest chunks (16 voxels: ~17k chunks per triangle, 2110 layers along z) and a GPU's.
  expectGpuEqualsCpu(quad, spec, CoarseMethod::Edt, gpu::shared::kVoxelizeMinChunkGroups, 16);
  expectGpuEqualsCpu(quad, spec, CoarseMethod::Edt, gpu::shared::kVoxelizeMaxChunkGroups,
                     gpu::shared::kVoxelizeChunkVoxelsGpu);
  EXPECT_EQ(largeTriangles(quad, spec, 16).first, 2u); // both in the second dispatch, in layers along z
  EXPECT_EQ(largeTriangles(quad, spec, gpu::shared::kVoxelizeChunkVoxelsGpu).first, 2u);
  CoarseSdfSettings shortest;
  shortest.chunkVoxels = 8; // below 16: refused, naming the setting's value
  EXPECT_THROW(builder().build(quad, spec, shortest), Error);
}

// A build over a change voxelizes the change box alone and keeps the seeds outside it. Two bunnies on a ground quad
// that spans the grid (a triangle range clipped to the box), the second moved by 3.4 voxels: the box holds its seeds
// before and after (two voxels of margin, as movedSeedBox gives). The distances after the build over the change are
// the full build's of the moved scene bit for bit, and its seeds (the voxels at distance -beta) are voxelizeCpu's
// there; with a GPU's 64-voxel chunks and a CPU device's 4096. A change box off the scene changes nothing; one
// partly outside the grid is refused.
TEST_F(CoarseSdfGpu, ABuildOverAChangeVoxelizesItsBoxAloneAndEqualsAFullBuild) {
  const SceneGeometry geo = sceneGeometry("bunny.json");
  std::vector<glm::vec4> corners = triangleCorners(geo);
  const Bounds& b = geo.bounds;
  const double w = b.maxExtent();
  const float g = float(b.min.y - 0.05 * w);
  const float gx0 = float(b.min.x - 2 * w), gx1 = float(b.max.x + 2 * w);
  const float gz0 = float(b.min.z - w), gz1 = float(b.max.z + w);
  const glm::vec4 q0(gx0, g, gz0, 1), q1(gx1, g, gz0, 1), q2(gx1, g, gz1, 1), q3(gx0, g, gz1, 1);
  const std::uint32_t bunnyTriangles = std::uint32_t(corners.size() / 3);
  corners.insert(corners.end(), {q0, q1, q2, q0, q2, q3});
  Bounds all = b;
  all.add(b.min - glm::dvec3(1.5 * w, 0.1 * w, 0.5 * w));
  all.add(b.max + glm::dvec3(1.5 * w, 0.1 * w, 0.5 * w));
  const GridSpec spec = GridSpec::fromBounds(all, 96, 0.02);
  // Instance 0: the ground; 1: a bunny where it is; 2: a bunny to its right, at offset @a x.
  auto place = [&](double x) {
    std::vector<gpu::shared::VoxelizeInstance> inst(3, identityInstance(bunnyTriangles));
    inst[0].firstTriangle = bunnyTriangles;
    inst[0].triangleCount = 2;
    inst[1].firstInstanceTriangle = 2;
    inst[2].firstInstanceTriangle = 2 + bunnyTriangles;
    inst[2].objectToFrame[0].w = float(x);
    return inst;
  };
  const double x0 = 0.8 * w, x1 = x0 + 3.4 * spec.voxelSize;
  // The moving bunny's voxels before and after, with two voxels of margin, clamped to the grid.
  const glm::dvec3 lo = (b.min + glm::dvec3(x0, 0, 0) - spec.origin) / spec.voxelSize - 2.0;
  const glm::dvec3 hi = (b.max + glm::dvec3(x1, 0, 0) - spec.origin) / spec.voxelSize + 2.0;
  const CoarseVoxelBox change{glm::max(glm::ivec3(glm::floor(lo)), glm::ivec3(0)),
                              glm::min(glm::ivec3(glm::floor(hi)), spec.dims - 1)};
  ASSERT_FALSE(change.empty());
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::Buffer cornerBuf, before, after;
  gpu::reserveAndUpload(*sCtx, cornerBuf, corners.data(), corners.size() * sizeof(glm::vec4), usage, "corners");
  const auto instBefore = place(x0), instAfter = place(x1);
  gpu::reserveAndUpload(*sCtx, before, instBefore.data(), instBefore.size() * sizeof(instBefore[0]), usage, "inst");
  gpu::reserveAndUpload(*sCtx, after, instAfter.data(), instAfter.size() * sizeof(instAfter[0]), usage, "inst");
  const std::uint32_t tris = 2 + 2 * bunnyTriangles; // every instance's
  const InstancedTriangles sceneBefore{cornerBuf, before, 3, tris}, sceneAfter{cornerBuf, after, 3, tris};
  const std::size_t n = spec.voxelCount();
  const std::vector<std::uint32_t> seeds = voxelizeCpu(placeInstanceCorners(corners, instAfter), spec);
  for (const std::uint32_t chunk : {gpu::shared::kVoxelizeChunkVoxelsGpu, gpu::shared::kVoxelizeChunkVoxelsCpu}) {
    SCOPED_TRACE(::testing::Message() << chunk << " voxels a chunk");
    CoarseSdfSettings s;
    s.keepTransform = true;
    s.chunkVoxels = chunk;
    CoarseSdfBuilder& cb = builder();
    auto run = [&](const InstancedTriangles& t, const CoarseVoxelBox* box) {
      gpu::CommandBuffer cmd(*sCtx);
      const float beta = cb.record(cmd.handle(), nullptr, t, spec, s, box);
      cmd.submitAndWait();
      std::vector<float> d(n);
      gpu::download(*sCtx, cb.distanceBuffer(), d.data(), n * 4);
      return std::make_pair(d, beta);
    };
    run(sceneBefore, nullptr);
    const auto [overChange, beta] = run(sceneAfter, &change);
    ASSERT_TRUE(cb.lastBuiltOverChange());
    EXPECT_EQ(cb.lastVoxelizedVoxels(), regionVoxels(change));
    EXPECT_LT(cb.lastVoxelizedVoxels(), n / 4) << "the box is a part of the grid";
    const std::vector<float> full = run(sceneAfter, nullptr).first;
    EXPECT_EQ(cb.lastVoxelizedVoxels(), n);
    std::size_t differ = 0, seedDiff = 0, seedCount = 0;
    for (std::size_t i = 0; i < n; ++i) {
      differ += std::memcmp(&overChange[i], &full[i], 4) != 0;
      seedDiff += (overChange[i] == -beta) != (seeds[i] != kNoSeed);
      seedCount += seeds[i] != kNoSeed;
    }
    EXPECT_EQ(differ, 0u) << "voxels whose distance differs from the full build's";
    EXPECT_EQ(seedDiff, 0u) << "of " << seedCount << " seeds";
    // A small change box where nothing moved: the field stays as it was.
    const CoarseVoxelBox corner{glm::ivec3(0), glm::ivec3(1)};
    const std::vector<float> same = run(sceneAfter, &corner).first;
    EXPECT_EQ(std::memcmp(same.data(), full.data(), n * 4), 0);
    EXPECT_EQ(cb.lastVoxelizedVoxels(), 8u);
  }
  const VoxelizePass pass(*sCtx);
  gpu::shared::VoxelizeParams p = voxelizeParams(spec, tris);
  p.clipHi.x = spec.dims.x; // one past the grid
  gpu::CommandBuffer cmd(*sCtx);
  EXPECT_THROW(pass.execute(cmd.handle(), nullptr, {sceneAfter}, {cornerBuf, cornerBuf, cornerBuf, cornerBuf}, {p}),
               Error);
}

// The pipeline's frames voxelize mesh-space triangles placed by their instances' transforms on the GPU: its
// nearest seeds equal the CPU reference's (the same placement, transformToFrame, then voxelizeCpu) bit for bit on
// the animated default scene and the bunny, in a frame away from the world's origin; and the placement is the
// scene's (the CPU's double-precision transform marks the same seeds but for rounding at voxel faces).
TEST_F(CoarseSdfGpu, InstancedTrianglesEqualTheCpuReference) {
  for (const char* name : {"default.json", "bunny.json"}) {
    SCOPED_TRACE(name);
    const Scene scene = loadScene(test::dataPath(std::string("scenes/") + name));
    const double time = 0.7;
    const Bounds bounds = buildSceneGeometry(scene, time).bounds;
    const glm::dvec3 origin = bounds.min - 0.1;
    const GridSpec spec = GridSpec::fromBounds(bounds, 128, 0.1).inFrame(origin);
    GpuSceneBvh bvh(*sCtx, scene, origin);
    bvh.update(time);
    CoarseSdfSettings s;
    s.method = CoarseMethod::Edt;
    const CoarseSdf gpu = builder().build(bvh.instancedTriangles(), spec, s);
    const std::vector<glm::vec4> placed = placeInstanceCorners(bvh.meshes().corners, bvh.voxelizeInstances());
    ASSERT_EQ(placed.size(), 3 * bvh.instancedTriangles().triangleCount);
    const std::vector<std::uint32_t> seeds = voxelizeCpu(placed, spec);
    EXPECT_EQ(gpu.nearest, exactEdtNearestCpu(seeds, spec.dims));
    const std::vector<std::uint32_t> scene64 = voxelizeCpu(triangleCorners(buildSceneGeometry(scene, time, origin)), spec);
    std::size_t seedCount = 0, differ = 0;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      seedCount += seeds[i] != kNoSeed;
      differ += seeds[i] != scene64[i];
    }
    EXPECT_GT(seedCount, 1000u);
    EXPECT_LE(differ, seedCount / 1000) << "of " << seedCount << " seeds";
  }
}

namespace {

/// Axis-aligned rectangles (two triangles each) on the faces of the lattice of voxel @a h, where a frame's rounding
/// decides which side touches them: a floor at y = 0, a wall at x = 7h, a slab at z = -3h, and a tilted quad.
std::vector<glm::vec4> latticeFaceQuads(double h) {
  std::vector<glm::vec4> c;
  auto quad = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 d) { // a, a + b, a + b + d, a + d
    const glm::vec4 p0(glm::vec3(a), 1), p1(glm::vec3(a + b), 1), p2(glm::vec3(a + b + d), 1), p3(glm::vec3(a + d), 1);
    c.insert(c.end(), {p0, p1, p2, p0, p2, p3});
  };
  quad({-30 * h, 0, -30 * h}, {60 * h, 0, 0}, {0, 0, 60 * h});
  quad({7 * h, 0, -20 * h}, {0, 12 * h, 0}, {0, 0, 30 * h});
  quad({-25 * h, 2 * h, -3 * h}, {40 * h, 0, 0}, {0, 9 * h, 0});
  quad({-9 * h, 1 * h, 4 * h}, {11 * h, 5 * h, 0}, {0, 2 * h, 13 * h});
  return c;
}

} // namespace

// A grid on the world's seed lattice (a cascade level) voxelizes each voxel by its world cell alone: after a scroll
// the seeds kept (SeedShiftPass) and those voxelized where the grid entered equal a full build of the moved grid bit
// for bit, and so do the distances, though the triangles lie on voxel faces where a frame's rounding decides; only
// the voxels that entered are voxelized, and after a shift by whole blocks the transform runs only over what the
// seeds that entered and left reach (its kept buffers moved); the seeds equal the CPU copy's, and are conservative and
// tight against the rectangles' exact overlap with each voxel (in double).
TEST_F(CoarseSdfGpu, SeedsOnTheWorldLatticeScrollWithTheGridAndEqualAFullBuild) {
  const double h = 0.05; // not a binary fraction: the rounding differs from frame to frame
  const std::vector<glm::vec4> corners = latticeFaceQuads(h);
  const auto tris = std::uint32_t(corners.size() / 3);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::Buffer cornerBuf, instBuf, scratch;
  gpu::reserveAndUpload(*sCtx, cornerBuf, corners.data(), corners.size() * sizeof(glm::vec4), usage, "corners");
  const gpu::shared::VoxelizeInstance identity = identityInstance(tris);
  gpu::reserveAndUpload(*sCtx, instBuf, &identity, sizeof(identity), usage, "instance");
  const InstancedTriangles world{cornerBuf, instBuf, 1, tris};
  const glm::ivec3 dims(37, 22, 33);
  auto gridAt = [&](const glm::ivec3& cell) {
    GridSpec g;
    g.dims = dims;
    g.voxelSize = h;
    g.origin = glm::dvec3(cell) * h;
    return g;
  };
  gpu::reserve(*sCtx, scratch, std::uint64_t(dims.x) * dims.y * dims.z * 4, usage, gpu::Buffer::Memory::Device,
               "scratch");
  CoarseSdfBuilder scrolled(*sCtx), fresh(*sCtx);
  CoarseSdfSettings s;
  s.keepTransform = true;
  auto record = [&](CoarseSdfBuilder& b, const glm::ivec3& cell, const glm::ivec3* shift) {
    s.seedLatticeCell = cell;
    gpu::CommandBuffer cmd(*sCtx);
    if (shift) b.recordScroll(cmd.handle(), *shift, scratch, false);
    b.record(cmd.handle(), nullptr, world, gridAt(cell), s);
    cmd.submitAndWait();
  };
  glm::ivec3 cell(-20, -3, -18);
  ASSERT_EQ(seedLatticeCell(gridAt(cell)), cell);
  record(scrolled, cell, nullptr);
  EXPECT_EQ(scrolled.readSeeds(dims), voxelizeCpu(corners, gridAt(cell), cell));
  const std::uint64_t voxels = std::uint64_t(dims.x) * dims.y * dims.z;
  int overScroll = 0;
  for (const glm::ivec3 shift : {glm::ivec3(3, 0, 0), glm::ivec3(0, 2, 0), glm::ivec3(0, 0, -4), glm::ivec3(4, 0, 0),
                                 glm::ivec3(-2, -1, 5), glm::ivec3(0, 0, 8), glm::ivec3(-4, 4, 0), glm::ivec3(0, -4, 0),
                                 glm::ivec3(0, 40, 0), glm::ivec3(0, -40, 0)}) {
    SCOPED_TRACE(::testing::Message() << "shift " << shift.x << "," << shift.y << "," << shift.z);
    cell += shift;
    record(scrolled, cell, &shift);
    record(fresh, cell, nullptr);
    std::uint64_t entered = 0;
    for (const CoarseVoxelBox& b : boxesOutside(dims, keptByShift(dims, shift))) entered += regionVoxels(b);
    EXPECT_EQ(scrolled.lastVoxelizedVoxels(), entered);
    const bool within = glm::all(glm::lessThan(glm::abs(shift), dims));
    if (within) EXPECT_LT(entered, voxels / 2);
    // Whole blocks after a build that followed no other scroll: the transform runs over what the seeds that entered
    // and left reach (the region of scrollChanges), the rest moved with the grid.
    const bool whole = glm::all(glm::equal(shift % RTSDF_COARSE_BLOCK, glm::ivec3(0)));
    EXPECT_EQ(scrolled.lastBuiltOverChange(), whole && within);
    if (scrolled.lastBuiltOverChange()) {
      ++overScroll;
      // Along one axis the boxes are slabs at the faces (54-85% of this sparse scene's grid is within its seed
      // distances of them); along two they span the grid, as here.
      const int axes = (shift.x != 0) + (shift.y != 0) + (shift.z != 0);
      if (axes == 1) EXPECT_LT(scrolled.readRegion().counts.z, voxels * 9 / 10) << "voxels transformed again";
    }
    const std::vector<std::uint32_t> seeds = scrolled.readSeeds(dims);
    EXPECT_EQ(seeds, fresh.readSeeds(dims));
    EXPECT_EQ(seeds, voxelizeCpu(corners, gridAt(cell), cell));
    std::vector<float> a(seeds.size()), b(seeds.size());
    gpu::download(*sCtx, scrolled.distanceBuffer(), a.data(), a.size() * 4);
    gpu::download(*sCtx, fresh.distanceBuffer(), b.data(), b.size() * 4);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * 4), 0);
  }
  EXPECT_EQ(overScroll, 5);
  // Conservative and tight: every voxel a rectangle overlaps by more than 1e-4 voxels is a seed, and every seed
  // comes within 1e-4 voxels of one (closed form, in double: the voxel box against each rectangle's box).
  const GridSpec g = gridAt(cell);
  const std::vector<std::uint32_t> seeds = scrolled.readSeeds(dims);
  std::size_t count = 0;
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x) {
        const glm::dvec3 lo = g.origin + glm::dvec3(x, y, z) * h, hi = lo + h;
        double nearest = HUGE_VAL; // the largest per-axis gap to the nearest rectangle (negative: overlap depth)
        for (std::size_t t = 0; t + 5 < 18; t += 6) { // the three axis-aligned rectangles
          glm::dvec3 rlo(HUGE_VAL), rhi(-HUGE_VAL);
          for (std::size_t k = t; k < t + 6; ++k) {
            rlo = glm::min(rlo, glm::dvec3(glm::vec3(corners[k])));
            rhi = glm::max(rhi, glm::dvec3(glm::vec3(corners[k])));
          }
          const glm::dvec3 gap = glm::max(rlo - hi, lo - rhi);
          nearest = std::min(nearest, std::max({gap.x, gap.y, gap.z}) / h);
        }
        const bool seed = seeds[g.linear(x, y, z)] != kNoSeed;
        count += seed;
        if (nearest < -1e-4) {
          ASSERT_TRUE(seed) << x << "," << y << "," << z;
        } else if (nearest > 1e-4 && seed) { // a seed of the tilted quad alone: within half a diagonal of it
          const glm::vec3 c(0.5 * (lo + hi));
          double d = HUGE_VAL;
          for (std::size_t k = 18; k < 24; k += 3)
            d = std::min(d, std::sqrt(double(distanceSquaredToTriangle(c, glm::vec3(corners[k]),
                                                                       glm::vec3(corners[k + 1]),
                                                                       glm::vec3(corners[k + 2])))));
          ASSERT_LE(d / h, 0.5 * std::sqrt(3.0) + 1e-4) << x << "," << y << "," << z;
        }
      }
  EXPECT_GT(count, 1000u);
}

// SeedShiftPass moves seeds as its CPU copy does, and the copy is what a grid voxelized after the move holds: the
// seeds packed at their new voxels, none where they entered.
TEST_F(CoarseSdfGpu, SeedShiftPassEqualsItsCpuCopy) {
  const glm::ivec3 dims(13, 9, 6);
  std::vector<std::uint32_t> seeds(std::size_t(dims.x) * dims.y * dims.z, kNoSeed);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x)
        if (gpu::shared::pcgHash(std::uint32_t((z * dims.y + y) * dims.x + x)) % 3 == 0)
          seeds[std::size_t((z * dims.y + y) * dims.x + x)] = gpu::shared::packSeed({x, y, z});
  const SeedShiftPass pass(*sCtx);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  for (const glm::ivec3 shift : {glm::ivec3(0), glm::ivec3(4, 0, 0), glm::ivec3(-3, 2, 1), glm::ivec3(0, 0, -6)}) {
    gpu::Buffer source, target;
    gpu::reserveAndUpload(*sCtx, source, seeds.data(), seeds.size() * 4, usage, "source");
    gpu::reserve(*sCtx, target, seeds.size() * 4, usage, gpu::Buffer::Memory::Device, "seeds");
    gpu::CommandBuffer cmd(*sCtx);
    pass.execute(cmd.handle(), nullptr, {source}, {target}, {glm::ivec4(dims, 0), glm::ivec4(shift, 0)});
    cmd.submitAndWait();
    std::vector<std::uint32_t> out(seeds.size());
    gpu::download(*sCtx, target, out.data(), out.size() * 4);
    const std::vector<std::uint32_t> cpu = shiftSeedsCpu(seeds, dims, shift);
    EXPECT_EQ(out, cpu);
    std::size_t moved = 0;
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          const glm::ivec3 from = glm::ivec3(x, y, z) + shift;
          const bool inside = glm::all(glm::greaterThanEqual(from, glm::ivec3(0))) &&
                              glm::all(glm::lessThan(from, dims));
          const std::uint32_t expected =
              inside && seeds[std::size_t((from.z * dims.y + from.y) * dims.x + from.x)] != kNoSeed
                  ? gpu::shared::packSeed({x, y, z})
                  : kNoSeed;
          moved += expected != kNoSeed;
          ASSERT_EQ(cpu[std::size_t((z * dims.y + y) * dims.x + x)], expected);
        }
    if (glm::all(glm::lessThan(glm::abs(shift), dims))) EXPECT_GT(moved, 20u);
    else EXPECT_EQ(moved, 0u) << "moved beyond the grid";
  }
  const gpu::Buffer small(*sCtx, 64, usage, gpu::Buffer::Memory::Device, "small");
  gpu::CommandBuffer cmd(*sCtx);
  EXPECT_THROW(pass.execute(cmd.handle(), nullptr, {small}, {small}, {glm::ivec4(dims, 0), glm::ivec4(0)}), Error);
}

// The voxels outside a kept box are covered once by boxesOutside's boxes, and keptByShift keeps exactly the voxels
// whose source lies in the grid; a grid is on the world's lattice only where its corner is a whole number of voxels.
TEST(SeedLattice, BoxesOutsideCoverTheRestOnceAndTheLatticeNeedsAWholeCorner) {
  const glm::ivec3 dims(7, 5, 6);
  for (const glm::ivec3 shift : {glm::ivec3(0), glm::ivec3(2, 0, 0), glm::ivec3(-1, 3, -2), glm::ivec3(0, 0, 6),
                                 glm::ivec3(9, 0, 0)}) {
    const CoarseVoxelBox kept = keptByShift(dims, shift);
    std::vector<int> covered(std::size_t(dims.x) * dims.y * dims.z, 0);
    std::vector<CoarseVoxelBox> boxes = boxesOutside(dims, kept);
    EXPECT_LE(boxes.size(), 6u);
    if (!kept.empty()) boxes.push_back(kept);
    for (const CoarseVoxelBox& b : boxes)
      for (int z = b.lo.z; z <= b.hi.z; ++z)
        for (int y = b.lo.y; y <= b.hi.y; ++y)
          for (int x = b.lo.x; x <= b.hi.x; ++x) ++covered[std::size_t((z * dims.y + y) * dims.x + x)];
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          EXPECT_EQ(covered[std::size_t((z * dims.y + y) * dims.x + x)], 1) << x << "," << y << "," << z;
          const glm::ivec3 from = glm::ivec3(x, y, z) + shift;
          const bool inside =
              glm::all(glm::greaterThanEqual(from, glm::ivec3(0))) && glm::all(glm::lessThan(from, dims));
          const bool inKept = !kept.empty() && glm::all(glm::greaterThanEqual(glm::ivec3(x, y, z), kept.lo)) &&
                              glm::all(glm::lessThanEqual(glm::ivec3(x, y, z), kept.hi));
          EXPECT_EQ(inKept, inside);
        }
  }
  GridSpec g;
  g.dims = dims;
  g.voxelSize = 0.05;
  g.origin = glm::dvec3(-20, 3, 7) * 0.05;
  EXPECT_EQ(seedLatticeCell(g), glm::ivec3(-20, 3, 7));
  g.origin.y += 1e-9;
  EXPECT_FALSE(seedLatticeCell(g).has_value()) << "a corner off the lattice";
  g.origin = glm::dvec3(double(kSeedLatticeCells), 0, 0) * 0.05;
  EXPECT_FALSE(seedLatticeCell(g).has_value()) << "too far for float cells";
}

// After a scroll, every fine voxel whose upsampled coarse SDF differs from its shifted value lies in a block that
// UpsampleBlocksPass's CPU copy lists from the changed voxels' marks and scrollUpsampleBoxes, on the CPU: the old
// grid's field upsampled (upsampleCoarse), shifted (the voxels that entered hold NaN), against the new grid's (its
// coarse values the old ones moved, random where it entered, a few changed). Dyadic grids, so that the two frames'
// trilinear weights are the same floats. The fine voxels are found in their blocks through upsampleBlockFineBegins,
// which must split the grid. The layers at the faces left behind are needed: without them voxels are missed.
TEST(ScrollUpsample, TheListedBlocksHoldEveryFineVoxelAScrollRewrites) {
  const glm::ivec3 dims(32, 24, 28), ratio(2);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  for (const glm::ivec3 shift : {glm::ivec3(4, 0, 0), glm::ivec3(-4, 0, 0), glm::ivec3(0, 4, -4),
                                 glm::ivec3(4, -4, 4), glm::ivec3(0, 0, 28)}) {
    SCOPED_TRACE(::testing::Message() << "shift " << shift.x << "," << shift.y << "," << shift.z);
    GridSpec oldCoarse;
    oldCoarse.dims = dims;
    oldCoarse.voxelSize = 0.25;
    oldCoarse.origin = glm::dvec3(-1.0, 0.5, 2.0);
    GridSpec oldFine = oldCoarse;
    oldFine.dims = dims * ratio;
    oldFine.voxelSize = 0.125;
    GridSpec newCoarse = oldCoarse, newFine = oldFine;
    newCoarse.origin += glm::dvec3(shift) * oldCoarse.voxelSize;
    newFine.origin = newCoarse.origin;
    std::vector<float> before(oldCoarse.voxelCount());
    for (float& c : before) c = value(rng);
    // The old values moved (0 where the grid entered: the shift's fill), and the new field: the same, random where
    // the grid entered, and two kept voxels changed at the corners of their blocks (so that their neighbours are
    // reached through the marks alone).
    std::vector<float> moved(before.size(), 0.0f), after(before.size());
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          const glm::ivec3 from = glm::ivec3(x, y, z) + shift;
          const std::size_t i = newCoarse.linear(x, y, z);
          if (oldCoarse.contains(from)) moved[i] = before[oldCoarse.linear(from.x, from.y, from.z)];
          after[i] = oldCoarse.contains(from) ? moved[i] : value(rng);
        }
    for (const glm::ivec3 v : {glm::ivec3(11, 11, 11), glm::ivec3(16, 8, 20)})
      if (oldCoarse.contains(v + shift)) after[newCoarse.linear(v.x, v.y, v.z)] += 0.5f;
    const std::vector<std::uint32_t> marks = changedBlockMarksCpu(moved, after, dims);
    auto boxesOf = [](const std::vector<CoarseVoxelBox>& list) {
      gpu::shared::UpsampleBoxes boxes{};
      boxes.count.x = int(list.size());
      for (std::size_t i = 0; i < list.size(); ++i) {
        boxes.lo[i] = glm::ivec4(list[i].lo, 0);
        boxes.hi[i] = glm::ivec4(list[i].hi, 0);
      }
      return boxes;
    };
    const std::vector<CoarseVoxelBox> scroll = scrollUpsampleBoxes(dims, shift);
    ASSERT_LE(scroll.size(), std::size_t(RTSDF_UPSAMPLE_MAX_BOXES));
    const std::vector<std::uint32_t> listed = upsampleBlocksCpu(marks, dims, boxesOf(scroll));
    // Without the face layers: the voxels that entered alone.
    const std::vector<std::uint32_t> enteredOnly =
        upsampleBlocksCpu(marks, dims, boxesOf(boxesOutside(dims, keptByShift(dims, shift))));
    // Each fine voxel's block, through the table (which must cover every voxel once along each axis).
    const std::vector<int> begins = upsampleBlockFineBegins(newCoarse, newFine);
    const glm::ivec3 bd = gpu::shared::coarseBlockDims(dims), fd = newFine.dims;
    std::vector<std::vector<int>> blockOf(3);
    for (int a = 0; a < 3; ++a) {
      const int at = gpu::shared::upsampleBlockFineAt(bd, a);
      EXPECT_EQ(begins[std::size_t(at)], 0);
      EXPECT_EQ(begins[std::size_t(at + bd[a])], fd[a]);
      blockOf[std::size_t(a)].assign(std::size_t(fd[a]), -1);
      for (int k = 0; k < bd[a]; ++k)
        for (int x = begins[std::size_t(at + k)]; x < begins[std::size_t(at + k + 1)]; ++x)
          blockOf[std::size_t(a)][std::size_t(x)] = k;
    }
    auto blockIndex = [&](const glm::ivec3& v) {
      const glm::ivec3 b(blockOf[0][std::size_t(v.x)], blockOf[1][std::size_t(v.y)], blockOf[2][std::size_t(v.z)]);
      return std::uint32_t((b.z * bd.y + b.y) * bd.x + b.x);
    };
    const glm::ivec3 fineShift = shift * ratio;
    std::uint64_t rewritten = 0, missed = 0, missedWithoutFaces = 0, inListed = 0;
    for (int z = 0; z < fd.z; ++z)
      for (int y = 0; y < fd.y; ++y)
        for (int x = 0; x < fd.x; ++x) {
          const glm::ivec3 v(x, y, z), from = v + fineShift;
          ASSERT_TRUE(blockOf[0][std::size_t(x)] >= 0 && blockOf[1][std::size_t(y)] >= 0 && blockOf[2][std::size_t(z)] >= 0);
          const std::uint32_t b = blockIndex(v);
          const bool isListed = std::binary_search(listed.begin(), listed.end(), b);
          inListed += isListed;
          const float shifted = oldFine.contains(from) ? upsampleCoarse(before, oldCoarse, oldFine, from) : NAN;
          if (shifted == upsampleCoarse(after, newCoarse, newFine, v)) continue; // NaN (entered) never equals
          ++rewritten;
          missed += !isListed;
          missedWithoutFaces += !std::binary_search(enteredOnly.begin(), enteredOnly.end(), b);
        }
    EXPECT_GT(rewritten, 0u);
    EXPECT_EQ(missed, 0u) << "of " << rewritten << " fine voxels the scroll rewrites";
    if (!keptByShift(dims, shift).empty()) {
      EXPECT_GT(missedWithoutFaces, 0u) << "the faces left behind clamp their cells anew";
      EXPECT_LT(inListed, newFine.voxelCount()) << "a part of the grid";
    }
  }
}

// ExactEdtPass's line runs for several change boxes cover every line of each box and no more lines than the boxes
// together (a scroll's two slabs, which span the same lines, run once).
TEST(ExactEdt, MergedLineRunsCoverTheBoxesLinesAndNoMore) {
  auto area = [](const glm::ivec4& r) { return std::int64_t(std::max(r.z - r.x, 0)) * std::max(r.w - r.y, 0); };
  const std::vector<glm::ivec4> slabs{{0, 0, 32, 32}, {0, 0, 32, 32}, {3, 4, 9, 9}};
  EXPECT_EQ(mergeLineRuns(slabs), std::vector<glm::ivec4>(1, glm::ivec4(0, 0, 32, 32)));
  const std::vector<glm::ivec4> apart{{0, 0, 32, 4}, {0, 28, 32, 32}};
  EXPECT_EQ(mergeLineRuns(apart).size(), 2u) << "two slabs apart stay apart";
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> at(0, 20);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<glm::ivec4> runs;
    for (int k = 0; k < 1 + trial % 3; ++k) {
      const int x0 = at(rng), y0 = at(rng);
      runs.emplace_back(x0, y0, x0 + at(rng) % 8, y0 + at(rng) % 8);
    }
    const std::vector<glm::ivec4> merged = mergeLineRuns(runs);
    std::int64_t before = 0, after = 0;
    for (const glm::ivec4& r : runs) before += area(r);
    for (const glm::ivec4& r : merged) after += area(r);
    EXPECT_LE(after, before);
    for (const glm::ivec4& r : runs)
      for (int a = r.x; a < r.z; ++a)
        for (int b = r.y; b < r.w; ++b)
          ASSERT_TRUE(std::any_of(merged.begin(), merged.end(), [&](const glm::ivec4& m) {
            return a >= m.x && a < m.z && b >= m.y && b < m.w;
          })) << "line " << a << "," << b << " of trial " << trial;
  }
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
    for (CoarseMethod v : {CoarseMethod::Jfa, CoarseMethod::OnePlusJfa, CoarseMethod::JfaPlusTwo}) {
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
