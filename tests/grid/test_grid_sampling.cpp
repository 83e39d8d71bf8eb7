// sampleWorldPoints / gradientWorldPoints against a field whose trilinear interpolant is known exactly: a linear
// function of the world position, which trilinear interpolation reproduces and whose gradient is constant.
#include "grid/GridSampling.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

const openvdb::Vec3d kSlope(2.0, -3.0, 0.5);

double linear(const openvdb::Vec3d& p) { return kSlope.dot(p) + 1.0; }

/// Voxels 0..15 on each axis of size 0.25 with the first centre at (-1, 0.5, 2), every one active and holding
/// linear(centre); the background is 7.
openvdb::FloatGrid::Ptr linearGrid() {
  openvdb::initialize();
  auto grid = openvdb::FloatGrid::create(7.0f);
  auto transform = openvdb::math::Transform::createLinearTransform(0.25);
  transform->postTranslate(openvdb::Vec3d(-1.0, 0.5, 2.0));
  grid->setTransform(transform);
  auto acc = grid->getAccessor();
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (int k = 0; k < 16; ++k) {
        const openvdb::Coord c(i, j, k);
        acc.setValue(c, float(linear(grid->indexToWorld(c))));
      }
  return grid;
}

template <class Real> std::vector<Real> pointsInside(const openvdb::FloatGrid& grid, int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 14.9); // the eight voxels around each point exist
  std::vector<Real> p;
  for (int i = 0; i < n; ++i) {
    const openvdb::Vec3d w = grid.indexToWorld(openvdb::Vec3d(u(rng), u(rng), u(rng)));
    p.insert(p.end(), {Real(w.x()), Real(w.y()), Real(w.z())});
  }
  return p;
}

template <class Real> void checkLinearField(double tolerance) {
  const auto grid = linearGrid();
  const std::vector<Real> p = pointsInside<Real>(*grid, 500);
  const std::size_t n = p.size() / 3;
  std::vector<Real> values(n), gradients(3 * n);
  rtsdf::sampleWorldPoints(*grid, p.data(), n, values.data());
  rtsdf::gradientWorldPoints(*grid, p.data(), n, gradients.data());
  for (std::size_t i = 0; i < n; ++i) {
    const openvdb::Vec3d w(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    EXPECT_NEAR(values[i], linear(w), tolerance) << "point " << i;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(gradients[3 * i + a], kSlope[a], 1e-3) << "point " << i << " axis " << a;
  }
}

} // namespace

TEST(GridSampling, ReproducesALinearFieldAndItsWorldGradientInFloat) { checkLinearField<float>(1e-4); }

TEST(GridSampling, ReproducesALinearFieldAndItsWorldGradientInDouble) { checkLinearField<double>(1e-5); }

TEST(GridSampling, VoxelCentresGiveTheStoredValues) {
  const auto grid = linearGrid();
  const openvdb::Coord c(3, 9, 14);
  const openvdb::Vec3d w = grid->indexToWorld(c);
  const double p[3] = {w.x(), w.y(), w.z()};
  double v = 0.0;
  rtsdf::sampleWorldPoints(*grid, p, 1, &v);
  EXPECT_NEAR(v, grid->tree().getValue(c), 1e-6);
}

TEST(GridSampling, BackgroundAwayFromTheVoxelsAndNanForNonFinitePoints) {
  const auto grid = linearGrid();
  const double p[6] = {100.0, 100.0, 100.0, NAN, 0.0, 0.0};
  double v[2], g[6];
  rtsdf::sampleWorldPoints(*grid, p, 2, v);
  rtsdf::gradientWorldPoints(*grid, p, 2, g);
  EXPECT_EQ(v[0], 7.0);
  EXPECT_TRUE(std::isnan(v[1]));
  EXPECT_EQ(g[0], 0.0);
  EXPECT_EQ(g[1], 0.0);
  EXPECT_EQ(g[2], 0.0);
  EXPECT_TRUE(std::isnan(g[3]) && std::isnan(g[4]) && std::isnan(g[5]));
}
