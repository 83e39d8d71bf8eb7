// The exact field on open scans of several pieces (separated patches, a non-manifold fin, floating fragments): its
// signs are the winding number's wherever it uses the pseudo-normal, and a mesh in millimetres gives the field of
// the same mesh in metres, in voxels.
#include "GeometryOf.h"
#include "TestUtil.h"
#include "metrics/FieldError.h"
#include "reference/ExactSdf.h"
#include "reference/WindingNumber.h"
#include "reference/WindingRegions.h"
#include "scene/MeshIO.h"
#include "scene/ScanMeshes.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace rtsdf;

namespace {

using test::geometryOf;

Mesh bunny() { return loadMeshFile(test::dataPath("meshes/bunny.obj")); }

/// The open scans of several pieces, small enough to sum every triangle's solid angle at every band voxel.
std::vector<std::pair<const char*, Mesh>> scans() {
  return {{"sphere in patches", makeSphereInPatches(4, 0.05f)}, {"scan in pieces", makeScanInPieces(bunny(), 12)}};
}

/// The exact field of @a geo on @a res voxels across with a band of @a bandVoxels voxels.
openvdb::FloatGrid::Ptr bake(const SceneGeometry& geo, int res, double bandVoxels, SignMethod sign,
                             ExactSdfStats* stats = nullptr) {
  GridSpec spec = GridSpec::fromBounds(geo.bounds, res, 0.0);
  spec = GridSpec::fromBounds(geo.bounds, res, bandVoxels * spec.voxelSize);
  ExactSdfOptions opt;
  opt.band = bandVoxels * spec.voxelSize;
  opt.sign = sign;
  opt.progress = false;
  return exactSignedDistance(geo, spec, opt, stats);
}

} // namespace

TEST(OpenScans, PiecesAndRimsAreFound) {
  for (const auto& [name, mesh] : scans()) {
    SCOPED_TRACE(name);
    const SceneGeometry geo = geometryOf(mesh);
    const WorldMesh& m = geo.meshes[0];
    const VertexTriangles around(m.positions.size(), m.triangles);
    // The same pieces as the orientation repair's (meshPieces), numbered alike.
    const MeshPieces pieces = connectedPieces(m, around), reference = meshPieces(m.triangles);
    EXPECT_EQ(pieces.pieceOf, reference.pieceOf);
    EXPECT_EQ(pieces.closed, reference.closed);
    EXPECT_EQ(WindingRegions(m, around, pieces).pieceCount(), pieces.count());
  }
  const SceneGeometry patches = geometryOf(makeSphereInPatches(4, 0.05f));
  EXPECT_EQ(meshPieces(patches.meshes[0].triangles).count(), 8u);
  // The scan: two halves, a fin and six discs (the holes cut no piece off).
  const SceneGeometry scan = geometryOf(makeScanInPieces(bunny(), 12));
  const WorldMesh& m = scan.meshes[0];
  ASSERT_FALSE(m.watertight);
  const VertexTriangles around(m.positions.size(), m.triangles);
  const WindingRegions regions(m, around, connectedPieces(m, around));
  EXPECT_GE(regions.pieceCount(), 9u);
  // The fin's edge has three faces: its closest points sign by the winding number wherever they are.
  const std::size_t fin = m.triangles.size() - 6 * 6 - 1;
  const glm::vec3 mid = 0.5f * (m.positions[m.triangles[fin].x] + m.positions[m.triangles[fin].y]);
  EXPECT_TRUE(regions.needed(mid, 0.0f, unsigned(fin), TriangleFeature::EdgeAB));
  EXPECT_TRUE(regions.needed(mid, 0.0f, unsigned(fin), TriangleFeature::VertexA));
  // Points on the faces: most are left to the pseudo-normal, those in another piece's box (near a disc, the fin or
  // the other half) are not.
  std::size_t left = 0;
  for (unsigned t = 0; t < m.triangles.size(); ++t) {
    const glm::uvec3 tri = m.triangles[t];
    const glm::vec3 c = (m.positions[tri.x] + m.positions[tri.y] + m.positions[tri.z]) / 3.0f;
    left += !regions.needed(c, 0.0f, t, TriangleFeature::Face);
  }
  EXPECT_GT(left, m.triangles.size() / 2);
  EXPECT_LT(left, m.triangles.size());
}

// Every band voxel of each scan has the sign of the exact winding number (the sum of every triangle's solid angle),
// except where that number is within 0.05 of a half (at the rims and gaps: ambiguous), while the winding number is
// evaluated at only a share of the voxels.
TEST(OpenScans, SignsAreTheBruteForceWindingNumbers) {
  for (const auto& [name, mesh] : scans()) {
    SCOPED_TRACE(name);
    const SceneGeometry geo = geometryOf(mesh);
    ASSERT_FALSE(geo.meshes[0].watertight);
    ExactSdfStats stats;
    const auto grid = bake(geo, 64, 3.0, SignMethod::Auto, &stats);
    const WindingNumberTree tree(geo.meshes[0].positions, geo.meshes[0].triangles);
    std::uint64_t checked = 0, wrong = 0, inside = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      const openvdb::Vec3d p = grid->transform().indexToWorld(it.getCoord());
      const double w = tree.evaluateExact({p.x(), p.y(), p.z()});
      if (std::fabs(w - 0.5) < 0.05) continue;
      ++checked;
      inside += w > 0.5;
      wrong += (*it < 0.0f) != (w > 0.5);
    }
    std::printf("%s: %llu triangles, winding number at %llu of %llu voxels, %llu of %llu checked signs wrong\n", name,
                (unsigned long long)geo.meshes[0].triangles.size(), (unsigned long long)stats.windingQueries,
                (unsigned long long)stats.activeVoxels, (unsigned long long)wrong, (unsigned long long)checked);
    EXPECT_GT(checked, 9 * stats.activeVoxels / 10);
    EXPECT_GT(inside, checked / 4);
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(stats.windingQueries, 0u);
    EXPECT_LT(stats.windingQueries, stats.activeVoxels / 2);
  }
}

// The per-voxel rule keeps the field of the hierarchical winding number evaluated at every voxel: same voxels, same
// distances, same signs, on the scans and on the teapot (pieces stuck into each other, signed by the winding number
// everywhere before the rule).
TEST(OpenScans, TheRuleKeepsTheWindingNumbersField) {
  std::vector<std::pair<const char*, SceneGeometry>> meshes;
  for (const auto& [name, mesh] : scans()) meshes.emplace_back(name, geometryOf(mesh));
  meshes.emplace_back("teapot", buildSceneGeometry(loadScene(test::dataPath("scenes/teapot.json"))));
  for (const auto& [name, geo] : meshes) {
    SCOPED_TRACE(name);
    ExactSdfStats rule, all;
    const auto fast = bake(geo, 96, 3.0, SignMethod::Auto, &rule);
    const auto winding = bake(geo, 96, 3.0, SignMethod::WindingNumber, &all);
    const FieldError e = compareFields(*fast, *winding);
    std::printf("%s at 96: winding number at %llu of %llu voxels\n", name, (unsigned long long)rule.windingQueries,
                (unsigned long long)rule.activeVoxels);
    EXPECT_EQ(e.voxels, all.activeVoxels);
    EXPECT_EQ(e.onlyInA + e.onlyInB, 0u);
    EXPECT_EQ(e.maxAbs, 0.0);
    EXPECT_EQ(e.signMismatches, 0u);
    EXPECT_LT(rule.windingQueries, rule.activeVoxels / 2);
  }
}

// A mesh in millimetres and the same mesh in metres, with the band given in voxels: the same grid, the same active
// voxels, and values 1000 times larger to float precision (in voxels: the same field). A closed mesh (pseudo-normal
// signs) and an open scan in pieces (the winding number's regions, whose reach scales with the mesh).
TEST(OpenScans, MillimetresAndMetresGiveTheSameFieldInVoxels) {
  for (const auto& [name, mesh] : {std::pair<const char*, Mesh>{"bunny", bunny()}, {"scan in pieces",
                                                                                     makeScanInPieces(bunny(), 12)}}) {
    SCOPED_TRACE(name);
    const SceneGeometry metres = geometryOf(mesh), millimetres = geometryOf(mesh, 1000.0f);
    const auto m = bake(metres, 80, 3.0, SignMethod::Auto), mm = bake(millimetres, 80, 3.0, SignMethod::Auto);
    EXPECT_EQ(m->activeVoxelCount(), mm->activeVoxelCount());
    EXPECT_EQ(m->evalActiveVoxelBoundingBox(), mm->evalActiveVoxelBoundingBox());
    const double h = mm->transform().voxelSize()[0];
    EXPECT_NEAR(h, 1000.0 * m->transform().voxelSize()[0], 1e-6 * h); // the float positions' rounding
    auto acc = mm->getConstAccessor();
    double worst = 0.0;
    std::uint64_t missing = 0, flipped = 0;
    for (auto it = m->cbeginValueOn(); it; ++it) {
      missing += !acc.isValueOn(it.getCoord());
      const float v = acc.getValue(it.getCoord());
      flipped += (v < 0.0f) != (*it < 0.0f);
      worst = std::max(worst, std::fabs(double(v) - 1000.0 * double(*it)) / h);
    }
    std::printf("%s: %llu voxels, largest difference %.3g voxels\n", name,
                (unsigned long long)m->activeVoxelCount(), worst);
    EXPECT_EQ(missing, 0u);
    EXPECT_EQ(flipped, 0u);
    EXPECT_LT(worst, 1e-4); // float rounding of positions and distances, relative to a voxel
  }
}
