// Closed pieces that pass through each other are a union on the GPU too (piece_union.glsl): every refinement mode
// against the closed form of two spheres' union, against the exact field's union (reference/PieceUnion, winding
// numbers) on two bunnies of which one moves, and against the shader's CPU copy (ClosedPieceUnionCpu).
#include "GpuFixture.h"
#include "TestUtil.h"
#include "reference/ExactSdf.h"
#include "scene/MeshRepair.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/SdfPipeline.h"
#include "sdf/pipeline/RayMask.h"
#include "sdf/refine/RefineCpu.h"
#include "sdf/scenebvh/ClosedPieces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>

using namespace rtsdf;

namespace {

struct PieceUnionTag : test::NoSuiteObjects {};
using PieceUnionGpu = test::VulkanSuite<PieceUnionTag>;

const glm::dvec3 kOffset(1.2, 0.2, 0.0); // the second sphere's centre: the two overlap by 0.8 along x

/// One mesh of two unit spheres through each other (two closed pieces), the second given inside-out as a careless
/// export would: the load's repair turns it outward.
Scene twoSpheres() {
  Mesh a = makeSphereMesh(1.0f, 4), b = makeSphereMesh(1.0f, 4);
  const unsigned base = unsigned(a.positions.size());
  for (const glm::vec3& p : b.positions) a.positions.push_back(p + glm::vec3(kOffset));
  for (const glm::uvec3& t : b.triangles) a.triangles.push_back(glm::uvec3(t.x, t.z, t.y) + glm::uvec3(base));
  Scene scene;
  scene.path = "two spheres";
  scene.meshReports.push_back(validateMesh(a));
  scene.meshes.push_back(std::move(a));
  scene.instances.push_back(Instance{"spheres", 0, {}, {}});
  return scene;
}

double twoSpheresDistance(const glm::dvec3& p) {
  return std::min(glm::length(p) - 1.0, glm::length(p - kOffset) - 1.0);
}

/// The bunny and a second instance of it half a bunny away, orbiting: closed pieces of two instances through each
/// other, moving.
Scene twoBunnies() {
  Scene scene = loadScene(test::dataPath("scenes/bunny.json"));
  Instance second = scene.instances.at(0);
  second.name = "bunny 2";
  second.transform.translation += glm::dvec3(0.45, 0.15, 0.1);
  second.animation.kind = Animation::Kind::Orbit;
  second.animation.center = scene.instances[0].transform.translation + glm::dvec3(0.3, 0.0, 0.0);
  second.animation.period = 4.0;
  scene.instances.push_back(second);
  return scene;
}

PipelineSettings settingsFor(RefineMode mode, int rays) {
  PipelineSettings s;
  s.band = 0.1; // the band (scene units) these cases were measured with
  s.coarseRes = 32;
  s.fineRes = 64;
  s.mode = mode;
  s.rays = rays;
  return s;
}

/// Masked fine voxels farther than half a voxel from the surface whose sign differs from @a truth's.
struct SignCount {
  std::uint64_t voxels = 0, wrong = 0;
  double share() const { return voxels ? double(wrong) / double(voxels) : 1.0; }
};
SignCount wrongSigns(const SdfPipeline& pipe, const std::function<double(const glm::dvec3&)>& truth) {
  const GridSpec& fs = pipe.fineSpec();
  const std::vector<float> fine = pipe.fineField();
  const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), fs, pipe.settings().band);
  SignCount c;
  for (std::uint32_t packed : mask.fineVoxels) {
    const glm::ivec3 v = test::unpackVoxel(packed);
    const double d = truth(fs.indexToWorld(glm::dvec3(v)));
    if (std::fabs(d) <= 0.5 * fs.voxelSize) continue;
    ++c.voxels;
    if ((fine[fs.linear(v.x, v.y, v.z)] < 0.0f) != (d < 0.0)) ++c.wrong;
  }
  return c;
}

Bounds boundsOver(const Scene& scene, std::initializer_list<double> times) {
  Bounds b;
  for (double t : times) b.add(buildSceneGeometry(scene, t).bounds);
  return b;
}

} // namespace

// The host's overlap list: closed pieces whose boxes touch or overlap, across instances; none when apart.
TEST(ClosedPieces, OverlapListHoldsTheClosedPiecesThatTouchAnother) {
  const Scene spheres = twoSpheres();
  EXPECT_EQ(ClosedPieceUnionCpu(spheres, 0.0).list().size(), 2u);
  Scene apart = spheres;
  apart.meshes[0] = makeSphereMesh(1.0f, 3);
  apart.meshReports[0] = validateMesh(apart.meshes[0]);
  apart.instances.push_back(apart.instances[0]);
  apart.instances[1].transform.translation = glm::dvec3(2.5, 0.0, 0.0);
  EXPECT_TRUE(ClosedPieceUnionCpu(apart, 0.0).list().empty());
  apart.instances[1].transform.translation = glm::dvec3(1.9, 0.0, 0.0);
  const ClosedPieceUnionCpu touching(apart, 0.0);
  EXPECT_EQ(touching.list().size(), 2u);
  // Inside the second instance, outside the first: inside another piece than the first's; not when the second's
  // own piece is the one skipped.
  EXPECT_TRUE(touching.insideAnother(glm::vec3(2.2f, 0.1f, 0.05f), 0, 0));
  EXPECT_FALSE(touching.insideAnother(glm::vec3(2.2f, 0.1f, 0.05f), 1, 0));
  EXPECT_FALSE(touching.insideAny(glm::vec3(3.05f, 0.0f, 0.0f)));
  EXPECT_FALSE(ClosedPieceUnionCpu(loadScene(test::dataPath("scenes/bunny.json")), 0.0).list().size());
}

// Every GPU mode against the closed form of the union of two spheres: the targets (closest mode at most
// 0.05% wrong signs, rays mode x = 10 at most 0.5% after its frames). Before the union rule: 10.1%, 4.0%, 0.18%.
TEST_F(PieceUnionGpu, EveryModeSignsTwoSpheresThroughEachOtherAsTheirUnion) {
  const Scene scene = twoSpheres();
  const Bounds bounds = buildSceneGeometry(scene, 0.0).bounds;
  struct Row { RefineMode mode; int rays, frames; double most; };
  for (const Row& r : {Row{RefineMode::Closest, 0, 1, 5e-4}, Row{RefineMode::Closest, 1, 4, 5e-4},
                       Row{RefineMode::Rays, 10, 16, 5e-3}}) {
    SCOPED_TRACE(::testing::Message() << (r.mode == RefineMode::Rays ? "rays" : "closest") << " x = " << r.rays);
    SdfPipeline pipe(*sCtx, scene, bounds, settingsFor(r.mode, r.rays));
    for (int f = 0; f < r.frames; ++f) pipe.runFrame(0.0);
    EXPECT_EQ(pipe.bvh().unionList().size(), 2u);
    const SignCount c = wrongSigns(pipe, twoSpheresDistance);
    std::printf("two spheres, %s x = %d: %llu of %llu wrong\n", r.mode == RefineMode::Rays ? "rays" : "closest",
                r.rays, (unsigned long long)c.wrong, (unsigned long long)c.voxels);
    EXPECT_GT(c.voxels, 5000u);
    EXPECT_LE(c.share(), r.most);
  }
}

// A pipeline lists only the overlapping pieces its grid can ask about (GpuSceneBvh::setUnionReach): every voxel of
// the refinement tests each listed piece, and a cascade level's scene keeps the world's moving instances, most far
// from it (in the 1000 m town 82-100 pieces a level, nearly all the cars'). Two pairs of spheres through each other,
// the second far off: a grid over the first lists its two pieces, and still signs them as their union; a grid over
// both lists all four.
TEST_F(PieceUnionGpu, APipelineListsOnlyThePiecesItsGridMeets) {
  Scene scene = twoSpheres();
  const glm::dvec3 far(40.0, 0.0, 0.0);
  Instance second = scene.instances.at(0);
  second.name = "spheres far off";
  second.transform.translation = far;
  scene.instances.push_back(second);
  Bounds nearBox = buildSceneGeometry(twoSpheres(), 0.0).bounds, both = buildSceneGeometry(scene, 0.0).bounds;
  SdfPipeline nearOnly(*sCtx, scene, nearBox, settingsFor(RefineMode::Closest, 0));
  nearOnly.runFrame(0.0);
  ASSERT_EQ(nearOnly.bvh().unionList().size(), 2u);
  for (const gpu::shared::UnionPiece& u : nearOnly.bvh().unionList())
    EXPECT_EQ(glm::floatBitsToUint(u.lo.w), 0u) << "the near pair's slot";
  const SignCount c = wrongSigns(nearOnly, twoSpheresDistance);
  EXPECT_GT(c.voxels, 5000u);
  EXPECT_LE(c.share(), 5e-4);
  SdfPipeline whole(*sCtx, scene, both, settingsFor(RefineMode::Closest, 0));
  whole.runFrame(0.0);
  EXPECT_EQ(whole.bvh().unionList().size(), 4u);
}

// Two bunnies of which one orbits through the other: closest mode's signs are the exact field's union (winding
// numbers of each closed piece, an independent implementation) at every moment, and its signs are the CPU copy's
// (the nearest triangle's side, then the same pieces, overlap list and ray parity) voxel for voxel.
TEST_F(PieceUnionGpu, ClosestModeOnMovingBunniesIsTheExactUnionAndItsCpuCopy) {
  const Scene scene = twoBunnies();
  const Bounds bounds = boundsOver(scene, {0.0, 0.5, 1.0});
  SdfPipeline pipe(*sCtx, scene, bounds, settingsFor(RefineMode::Closest, 0));
  for (double time : {0.0, 0.5, 1.0}) {
    SCOPED_TRACE(::testing::Message() << "time " << time);
    pipe.runFrame(time);
    EXPECT_FALSE(pipe.bvh().unionList().empty());
    const SceneGeometry geo = buildSceneGeometry(scene, time);
    const ExactDistanceField exact(geo);
    const SignCount c = wrongSigns(pipe, [&](const glm::dvec3& p) { return exact.signedDistance(glm::vec3(p)); });
    EXPECT_GT(c.voxels, 10000u);
    EXPECT_LE(c.share(), 5e-4) << c.wrong << " of " << c.voxels;

    // The CPU copy in the pipeline's frame, voxel by voxel (positions as the GPU computes them).
    const ClosedPieceUnionCpu copy(scene, time, pipe.frameOrigin());
    const GridSpec fs = pipe.fineSpec().inFrame(pipe.frameOrigin());
    const std::vector<float> fine = pipe.fineField();
    const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), pipe.fineSpec(), pipe.settings().band);
    std::uint64_t unionInside = 0, differ = 0, compared = 0;
    for (std::uint32_t packed : mask.fineVoxels) {
      const glm::ivec3 v = test::unpackVoxel(packed);
      const glm::vec3 p = glm::vec3(fs.origin) + (glm::vec3(v) + 0.5f) * float(fs.voxelSize);
      const glm::vec3 pw = glm::vec3(glm::dvec3(p) + pipe.frameOrigin());
      ExactDistanceField::Hit hit;
      if (!exact.closest(pw, INFINITY, hit) || hit.distance < 0.5f * float(fs.voxelSize)) continue;
      ++compared;
      const bool nearestSays = exact.insideNearestPiece(pw, hit);
      const bool byUnion = !nearestSays && copy.insideAnother(p, hit.mesh, hit.triangle);
      unionInside += byUnion;
      if ((fine[pipe.fineSpec().linear(v.x, v.y, v.z)] < 0.0f) != (nearestSays || byUnion)) ++differ;
    }
    EXPECT_GT(unionInside, 100u); // the union decides somewhere
    EXPECT_LE(differ, compared / 5000) << differ << " of " << compared;
  }
}

// Rays mode's first frame against refineRaysCpu with the union: the same rays, votes and union, on the two bunnies.
TEST_F(PieceUnionGpu, RaysFirstFrameEqualsTheCpuReferenceWithTheUnion) {
  const Scene scene = twoBunnies();
  PipelineSettings s = settingsFor(RefineMode::Rays, 4);
  s.seed = 11;
  SdfPipeline pipe(*sCtx, scene, buildSceneGeometry(scene, 0.0).bounds, s);
  pipe.runFrame(0.0);
  const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), pipe.fineSpec(), s.band);
  const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
  const ClosedPieceUnionCpu pieces(scene, 0.0, geo.origin);
  const float beta = float(0.5 * pipe.coarseSpec().voxelSize);
  const std::vector<float> withUnion = refineRaysCpu(geo, pipe.coarseField(), pipe.coarseSpec(), pipe.fineSpec(),
                                                     mask.fineVoxels, 4, 1, 11, beta, &pieces);
  const std::vector<float> votesOnly = refineRaysCpu(geo, pipe.coarseField(), pipe.coarseSpec(), pipe.fineSpec(),
                                                     mask.fineVoxels, 4, 1, 11, beta);
  const std::vector<float> gpu = pipe.fineField();
  const GridSpec& fs = pipe.fineSpec();
  std::size_t differ = 0, byUnion = 0;
  for (std::size_t k = 0; k < mask.fineVoxels.size(); ++k) {
    const glm::ivec3 v = test::unpackVoxel(mask.fineVoxels[k]);
    const float g = gpu[fs.linear(v.x, v.y, v.z)];
    if (std::fabs(g - withUnion[k]) > 1e-4f * (1.0f + std::fabs(withUnion[k]))) ++differ;
    if ((withUnion[k] < 0.0f) != (votesOnly[k] < 0.0f)) ++byUnion;
  }
  EXPECT_GT(mask.fineVoxels.size(), 10000u);
  EXPECT_GT(byUnion, 100u) << "the union must decide some voxels for this test to mean anything";
  EXPECT_LE(differ, mask.fineVoxels.size() / 500) << differ << " of " << mask.fineVoxels.size();
}

// Diagnostic (run by hand): the largest errors of closest mode's dense fine field at size @c RTSDF_DIAG_SIZE against
// the exact field, over the voxels a level set of the dense field would hold (|f| <= band), each with whether it was
// refined (in the ray mask) and what the exact field says there.
TEST_F(PieceUnionGpu, DISABLED_LargestClosestErrorsOnTheDefaultScene) {
  const char* sizeEnv = std::getenv("RTSDF_DIAG_SIZE");
  const int coarse = sizeEnv ? std::atoi(sizeEnv) : 64;
  const char* sceneEnv = std::getenv("RTSDF_DIAG_SCENE");
  const Scene scene = loadScene(test::dataPath(sceneEnv ? sceneEnv : "scenes/default.json"));
  const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
  PipelineSettings s;
  s.band = 0.1; // the band (scene units) these cases were measured with
  s.coarseRes = coarse;
  s.fineRes = 2 * coarse;
  s.mode = RefineMode::Closest;
  s.rays = std::getenv("RTSDF_DIAG_RAYS") ? std::atoi(std::getenv("RTSDF_DIAG_RAYS")) : 0;
  s.fullRecompute = true;
  if (std::getenv("RTSDF_DIAG_SPARSE")) s.fineStorage = FineStorage::Sparse; // size L on lavapipe
  SdfPipeline pipe(*sCtx, scene, geo.bounds, s);
  for (int f = 0; f < (s.rays ? 4 : 1); ++f) pipe.runFrame(0.0); // sign rays settle after 4 refinements
  const GridSpec& fs = pipe.fineSpec();
  const std::vector<float> fine = pipe.fineField();
  const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), fs, s.band);
  std::vector<char> masked(fs.voxelCount(), 0);
  for (std::uint32_t p : mask.fineVoxels) masked[fs.linear(p & 1023u, (p >> 10) & 1023u, (p >> 20) & 1023u)] = 1;
  const ExactDistanceField exact(geo);
  struct Bad { double err; glm::ivec3 v; float f, d; bool masked; unsigned mesh; bool nearestSays; };
  std::vector<Bad> worst;
  double maxMasked = 0.0, maxAll = 0.0;
  for (int z = 0; z < fs.dims.z; ++z)
    for (int y = 0; y < fs.dims.y; ++y)
      for (int x = 0; x < fs.dims.x; ++x) {
        const float f = fine[fs.linear(x, y, z)];
        if (std::fabs(f) > s.band) continue;
        const glm::vec3 p(fs.indexToWorld(glm::dvec3(x, y, z)));
        ExactDistanceField::Hit hit;
        if (!exact.closest(p, INFINITY, hit)) continue;
        const float d = exact.inside(p, hit) ? -hit.distance : hit.distance;
        if (std::fabs(d) > s.band) continue; // a level set of the exact field would not hold it
        const double err = std::fabs(double(f) - d) / fs.voxelSize;
        const bool m = masked[fs.linear(x, y, z)] != 0;
        maxAll = std::max(maxAll, err);
        if (m) maxMasked = std::max(maxMasked, err);
        if (err > 0.5) worst.push_back({err, {x, y, z}, f, d, m, hit.mesh, exact.insideNearestPiece(p, hit)});
      }
  std::sort(worst.begin(), worst.end(), [](const Bad& a, const Bad& b) { return a.err > b.err; });
  std::printf("size %d/%d: max error all %.3f, refined %.3f voxels; %zu voxels over 0.5\n", coarse, 2 * coarse, maxAll,
              maxMasked, worst.size());
  for (std::size_t k = 0; k < std::min<std::size_t>(worst.size(), 25); ++k) {
    const Bad& b = worst[k];
    std::printf("  err %.3f at (%d %d %d) f %.5f exact %.5f masked %d nearest instance %s nearestSays %d\n", b.err,
                b.v.x, b.v.y, b.v.z, b.f, b.d, int(b.masked), geo.meshes[b.mesh].instance.c_str(), int(b.nearestSays));
  }
}

// Measurement (run by hand): the sign suite's two cases of closed pieces through each other at its size (fine 96,
// coarse 48, band 3 voxels), closest mode x = 0 (1 frame) and x = 1 (4 frames): wrong signs over the refined voxels
// farther than 0.1 voxel from the closed form's surface.
TEST_F(PieceUnionGpu, DISABLED_SignSuiteOverlapCasesAt96) {
  Scene shell = twoSpheres();
  {
    Mesh a = makeSphereMesh(1.0f, 4), b = makeSphereMesh(0.5f, 3);
    const unsigned base = unsigned(a.positions.size());
    for (const glm::vec3& p : b.positions) a.positions.push_back(p);
    for (const glm::uvec3& t : b.triangles) a.triangles.push_back(glm::uvec3(t.x, t.z, t.y) + glm::uvec3(base));
    shell.meshReports[0] = validateMesh(a);
    shell.meshes[0] = std::move(a);
  }
  const auto ball = [](const glm::dvec3& p) { return glm::length(p) - 1.0; };
  struct Case { const char* name; Scene scene; std::function<double(const glm::dvec3&)> truth; };
  for (const Case& c : {Case{"two spheres through each other", twoSpheres(), twoSpheresDistance},
                        Case{"sphere with an inner shell", shell, ball}}) {
    const Bounds bounds = buildSceneGeometry(c.scene, 0.0).bounds;
    for (int rays : {0, 1}) {
      PipelineSettings s = settingsFor(RefineMode::Closest, rays);
      s.coarseRes = 48;
      s.fineRes = 96;
      s.band = 3.0 * bounds.maxExtent() / (96 - 6);
      SdfPipeline pipe(*sCtx, c.scene, bounds, s);
      for (int f = 0; f < (rays ? 4 : 1); ++f) pipe.runFrame(0.0);
      const GridSpec& fs = pipe.fineSpec();
      const std::vector<float> fine = pipe.fineField();
      const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), fs, s.band);
      std::uint64_t n = 0, wrong = 0;
      for (std::uint32_t packed : mask.fineVoxels) {
        const glm::ivec3 v = test::unpackVoxel(packed);
        const float f = fine[fs.linear(v.x, v.y, v.z)];
        const double d = c.truth(fs.indexToWorld(glm::dvec3(v)));
        if (std::fabs(f) > s.band || std::fabs(d) <= 0.1 * fs.voxelSize) continue;
        ++n;
        wrong += (f < 0.0f) != (d < 0.0);
      }
      std::printf("%s, closest x = %d: %.3f%% wrong (%llu of %llu)\n", c.name, rays, 100.0 * double(wrong) / double(n),
                  (unsigned long long)wrong, (unsigned long long)n);
    }
  }
}
