#include "grid/VdbIO.h"
#include "metrics/FieldError.h"
#include "util/Error.h"

#include <gtest/gtest.h>

using namespace rtsdf;

namespace {
openvdb::FloatGrid::Ptr gridWith(const std::vector<std::pair<openvdb::Coord, float>>& values, double h) {
  openvdb::initialize();
  auto g = openvdb::FloatGrid::create(1.0f);
  g->setTransform(openvdb::math::Transform::createLinearTransform(h));
  auto acc = g->getAccessor();
  for (const auto& [c, v] : values) acc.setValueOn(c, v);
  return g;
}
} // namespace

TEST(FieldError, StatisticsInVoxelsAndSignRules) {
  const double h = 0.5;
  const auto a = gridWith({{{0, 0, 0}, 1.0f}, {{1, 0, 0}, -1.0f}, {{2, 0, 0}, 0.0f}, {{3, 0, 0}, 2.0f}, {{9, 9, 9}, 1.0f}}, h);
  const auto b = gridWith({{{0, 0, 0}, 1.5f}, {{1, 0, 0}, 1.0f}, {{2, 0, 0}, -0.25f}, {{3, 0, 0}, 2.0f}, {{7, 7, 7}, 1.0f}}, h);
  const FieldError e = compareFields(*a, *b);
  EXPECT_EQ(e.voxels, 4u);
  EXPECT_EQ(e.onlyInA, 1u);
  EXPECT_EQ(e.onlyInB, 1u);
  // |differences| in voxels: 1, 4, 0.5, 0.
  EXPECT_DOUBLE_EQ(e.meanAbs, 5.5 / 4);
  EXPECT_DOUBLE_EQ(e.maxAbs, 4.0);
  EXPECT_DOUBLE_EQ(e.rms, std::sqrt((1.0 + 16.0 + 0.25) / 4));
  // (1,0,0) is a wrong sign; (2,0,0) lies on the surface in A and does not count.
  EXPECT_EQ(e.signMismatches, 1u);
  EXPECT_DOUBLE_EQ(e.signErrorRate(), 0.25);
}

/// A level set of f on every voxel of [lo, hi]^3 with voxel size h, voxel (0,0,0)'s centre at @a offset.
template <class F>
openvdb::FloatGrid::Ptr fieldGrid(const F& f, double h, const openvdb::Vec3d& offset, int lo, int hi) {
  openvdb::initialize();
  auto g = openvdb::FloatGrid::create(1.0f);
  g->setTransform(openvdb::math::Transform::createLinearTransform(h));
  g->transform().postTranslate(offset);
  auto acc = g->getAccessor();
  for (int x = lo; x <= hi; ++x)
    for (int y = lo; y <= hi; ++y)
      for (int z = lo; z <= hi; ++z) acc.setValueOn({x, y, z}, float(f(g->indexToWorld(openvdb::Coord(x, y, z)))));
  return g;
}

double plane(const openvdb::Vec3d& p) { return 0.3 * p.x() - 0.5 * p.y() + 0.2 * p.z() - 0.05; }

TEST(FieldError, ALatticeShiftedByWholeVoxelsIsReadWithoutResampling) {
  const auto a = fieldGrid(plane, 0.1, {0, 0, 0}, 0, 9);
  const auto b = fieldGrid(plane, 0.1, {0.3, -0.2, 0.0}, -5, 5); // B's (i,j,k) is A's (i+3, j-2, k)
  const GridMatch m = matchGrids(*a, *b);
  ASSERT_EQ(m.alignment, GridAlignment::Shifted) << m.description;
  EXPECT_EQ(m.shift, openvdb::Coord(-3, 2, 0));
  const FieldError e = compareFields(*a, *b);
  EXPECT_EQ(e.alignment, GridAlignment::Shifted);
  // A's x in [0, 9] meets B's [-5, 5] + 3 = [-2, 8]; y: [0, 9] meets [-5, 5] - 2 = [-7, 3]; z: [0, 5].
  EXPECT_EQ(e.voxels, 9u * 4u * 6u);
  EXPECT_EQ(e.onlyInA, 1000u - e.voxels);
  EXPECT_EQ(e.onlyInB, 1331u - e.voxels);
  EXPECT_LT(e.maxAbs, 1e-5); // the same points, up to the float rounding of the two world positions
}

TEST(FieldError, AnotherVoxelSizeOrAFractionalOffsetIsResampledTrilinearly) {
  const auto a = fieldGrid(plane, 0.1, {0, 0, 0}, 0, 9);
  for (const auto& [h, offset] : {std::pair{0.1, openvdb::Vec3d(0.037, -0.011, 0.052)},
                                  std::pair{0.07, openvdb::Vec3d(0.0, 0.0, 0.0)}}) {
    // Trilinear interpolation reproduces a linear field: the only differences are float rounding and the offset.
    const auto b = fieldGrid([](const openvdb::Vec3d& p) { return plane(p) + 0.02; }, h, offset, -3, 16);
    ASSERT_EQ(matchGrids(*a, *b).alignment, GridAlignment::Resampled);
    const FieldError e = compareFields(*a, *b);
    EXPECT_EQ(e.alignment, GridAlignment::Resampled);
    EXPECT_EQ(e.voxels, 1000u); // B's stencil covers all of A
    EXPECT_NEAR(e.meanAbs, 0.2, 1e-4) << h; // 0.02 world = 0.2 of A's voxels
    EXPECT_NEAR(e.maxAbs, 0.2, 1e-4) << h;
  }
}

TEST(FieldError, ResamplingUsesOnlyStencilsWhoseEightVoxelsAreActive) {
  const auto a = fieldGrid(plane, 0.1, {0, 0, 0}, 0, 3);
  const auto b = fieldGrid(plane, 0.1, {0.03, 0.03, 0.03}, -1, 3); // A's voxel c samples between B's c-1 and c
  b->tree().setValueOff(openvdb::Coord(1, 1, 1), 100.0f); // an inactive value that must not leak in
  const FieldError e = compareFields(*a, *b);
  EXPECT_EQ(e.onlyInA, 8u); // the 8 A voxels whose stencil holds B's (1,1,1)
  EXPECT_EQ(e.voxels, 56u);
  EXPECT_LT(e.maxAbs, 1e-5);
  EXPECT_EQ(e.onlyInB, 124u - 63u); // B's active voxels whose centre is in no A voxel: those outside [0, 3]^3
}

TEST(FieldError, AgainstAFunction) {
  const auto a = gridWith({{{0, 0, 0}, 0.0f}, {{2, 0, 0}, 1.0f}}, 0.5); // world x = 0 and 1
  const FieldError e = compareWithFunction(*a, [](const openvdb::Vec3d& p) { return p.x() - 0.25; });
  EXPECT_EQ(e.voxels, 2u);
  EXPECT_DOUBLE_EQ(e.maxAbs, 0.5); // 0.25 world at x = 0 and x = 1 -> 0.5 voxels
  EXPECT_EQ(e.signMismatches, 0u); // the first voxel is on the surface
  const FieldError skip = compareWithFunction(*a, [](const openvdb::Vec3d& p) { return p.x() - 0.25; }, 0.3);
  EXPECT_EQ(skip.voxels, 1u); // only x = 1 is farther than 0.3 from the reference surface
}

TEST(FieldError, DenseFieldAgainstAReferenceCountsEveryReferenceVoxel) {
  GridSpec spec;
  spec.dims = {4, 1, 1};
  spec.voxelSize = 0.5;
  // Reference voxels: (0..3, 0, 0) and one outside the dense grid.
  const auto ref = gridWith({{{0, 0, 0}, 1.0f}, {{1, 0, 0}, -0.5f}, {{2, 0, 0}, 0.25f}, {{3, 0, 0}, 2.0f},
                             {{7, 0, 0}, 1.0f}}, 0.5);
  // The dense field is far off at voxel 3 (a level set from it with a narrow band would drop that voxel).
  const std::vector<float> dense{1.0f, 0.5f, 0.25f, 9.0f};
  const FieldError e = compareDenseWithReference(dense, spec, *ref);
  EXPECT_EQ(e.voxels, 4u);
  EXPECT_EQ(e.onlyInB, 1u);
  // |differences| in voxels: 0, 2, 0, 14.
  EXPECT_DOUBLE_EQ(e.meanAbs, 16.0 / 4);
  EXPECT_DOUBLE_EQ(e.maxAbs, 14.0);
  EXPECT_EQ(e.signMismatches, 1u);
  EXPECT_THROW(compareDenseWithReference({1.0f}, spec, *ref), Error);
}
