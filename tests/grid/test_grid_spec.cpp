#include "grid/GridSpec.h"
#include "util/Memory.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace rtsdf;

TEST(GridSpec, FollowsSceneBoundsWithAnyDims) {
  const Bounds b{{-1.0, 0.0, -0.25}, {1.0, 0.5, 0.25}};
  const GridSpec g = GridSpec::fromBounds(b, 64, 0.0);
  EXPECT_DOUBLE_EQ(g.voxelSize, 2.0 / 64);
  EXPECT_EQ(g.dims, glm::ivec3(64, 16, 16));
  EXPECT_NEAR(g.origin.x, -1.0, 1e-12);
  EXPECT_NEAR(g.origin.y, 0.0, 1e-12);

  // Non-power-of-two, non-cubic: 37 across x; the others round up and stay centred.
  const GridSpec h = GridSpec::fromBounds({{0, 0, 0}, {3.7, 6.4, 2.0}}, 64, 0.0);
  EXPECT_DOUBLE_EQ(h.voxelSize, 0.1);
  EXPECT_EQ(h.dims, glm::ivec3(37, 64, 20));
}

TEST(GridSpec, PaddingAddsVoxelsAndKeepsVoxelSize) {
  const Bounds b{{0, 0, 0}, {2, 1, 1}};
  const GridSpec g = GridSpec::fromBounds(b, 20, 0.3);
  EXPECT_DOUBLE_EQ(g.voxelSize, 0.1);
  EXPECT_EQ(g.dims, glm::ivec3(26, 16, 16));
  const Bounds gb = g.bounds();
  EXPECT_LE(gb.min.x, -0.3 + 1e-12);
  EXPECT_GE(gb.max.x, 2.3 - 1e-12);
}

TEST(GridSpec, CellCentredMappingRoundTrips) {
  const GridSpec g = GridSpec::fromBounds({{-1, -2, -3}, {1, 2, 3}}, 30, 0.05);
  const glm::dvec3 c0 = g.indexToWorld(glm::dvec3(0));
  EXPECT_NEAR(c0.x, g.origin.x + 0.5 * g.voxelSize, 1e-12);
  for (const glm::dvec3 ijk : {glm::dvec3(0), glm::dvec3(3, 7, 11), glm::dvec3(g.dims - 1), glm::dvec3(1.25, 2.5, 0.75)}) {
    const glm::dvec3 back = g.worldToIndex(g.indexToWorld(ijk));
    EXPECT_NEAR(back.x, ijk.x, 1e-9);
    EXPECT_NEAR(back.y, ijk.y, 1e-9);
    EXPECT_NEAR(back.z, ijk.z, 1e-9);
  }
  EXPECT_EQ(g.linear(1, 0, 0), 1u);
  EXPECT_EQ(g.linear(0, 1, 0), std::uint64_t(g.dims.x));
  EXPECT_EQ(g.linear(0, 0, 1), std::uint64_t(g.dims.x) * g.dims.y);
}

TEST(GridSpec, FlatSceneAndSingleVoxel) {
  const GridSpec flat = GridSpec::fromBounds({{0, 0, 0}, {1, 0, 1}}, 8, 0.0);
  EXPECT_EQ(flat.dims, glm::ivec3(8, 1, 8));
  const GridSpec one = GridSpec::fromBounds({{0, 0, 0}, {1, 1, 1}}, 1, 0.0);
  EXPECT_EQ(one.dims, glm::ivec3(1));
  const GridSpec point = GridSpec::fromBounds({{1, 1, 1}, {1, 1, 1}}, 4, 0.5);
  EXPECT_EQ(point.dims, glm::ivec3(4));
}

TEST(GridSpec, RejectsBadSettings) {
  const Bounds b{{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(GridSpec::fromBounds(b, 0, 0.0), Error);
  EXPECT_THROW(GridSpec::fromBounds(b, GridSpec::kMaxResolution + 1, 0.0), Error);
  EXPECT_THROW(GridSpec::fromBounds(b, 8, -1.0), Error);
  EXPECT_THROW(GridSpec::fromBounds(b, 8, std::numeric_limits<double>::quiet_NaN()), Error);
  EXPECT_THROW(GridSpec::fromBounds(Bounds{}, 8, 0.0), Error);
  EXPECT_THROW(GridSpec::fromBounds({{0, 0, 0}, {INFINITY, 1, 1}}, 8, 0.0), Error);
  EXPECT_THROW(GridSpec::fromBounds({{1, 1, 1}, {1, 1, 1}}, 8, 0.0), Error); // a point and no padding
}

TEST(GridSpec, MemoryCheckRefusesBeforeAllocating) {
  const GridSpec g = GridSpec::fromBounds({{0, 0, 0}, {1, 1, 1}}, 4096, 0.0);
  EXPECT_THROW(checkDenseMemory(g, 4, 1ull << 30, "test"), Error);
  EXPECT_NO_THROW(checkDenseMemory(GridSpec::fromBounds({{0, 0, 0}, {1, 1, 1}}, 64, 0.0), 4, 1ull << 30, "test"));
  EXPECT_GT(physicalMemoryBytes(), 0u);
}
