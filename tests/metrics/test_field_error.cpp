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

TEST(FieldError, RefusesGridsOnDifferentVoxels) {
  const auto a = gridWith({{{0, 0, 0}, 1.0f}}, 0.5);
  const auto b = gridWith({{{0, 0, 0}, 1.0f}}, 0.25);
  EXPECT_THROW(compareFields(*a, *b), Error);
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
