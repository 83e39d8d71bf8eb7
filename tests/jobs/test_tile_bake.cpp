// Tiled exact bakes: the slabs cover the grid once in whole leaves, each tile holds only its slab's leaves, the
// merged tiles equal the whole bake in every voxel and tile (empty tiles and uneven slabs included), the
// comparison sees a single changed voxel, and bad tilings are refused naming the setting.
#include "grid/VdbIO.h"
#include "jobs/TileBake.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <string>

using namespace rtsdf;

namespace {

BakeOptions bunnyBake(int res) {
  BakeOptions o;
  o.scene = std::string(RTSDF_DATA_DIR) + "/scenes/bunny.json";
  o.method = BakeMethod::Exact;
  o.resolution = res;
  o.pipeline.band = 0.1;
  return o;
}

std::vector<openvdb::FloatGrid::Ptr> bakeTiles(const Scene& scene, const BakeOptions& bake, int tiles) {
  std::vector<openvdb::FloatGrid::Ptr> grids;
  for (int t = 0; t < tiles; ++t) {
    TileBakeOptions o;
    o.bake = bake;
    o.tiles = tiles;
    o.tile = t;
    grids.push_back(bakeTile(scene, o).grid);
  }
  return grids;
}

} // namespace

TEST(TileBake, SlabsCoverTheGridOnceInWholeLeaves) {
  GridSpec spec;
  spec.dims = {70, 41, 23};
  for (int tiles : {1, 3, 9, 12}) {
    const auto boxes = tileBoxes(spec, tiles);
    ASSERT_EQ(boxes.size(), std::size_t(tiles));
    int next = 0;
    for (const auto& box : boxes) {
      if (box.empty()) continue; // more tiles than leaves along x: 12 > 9
      EXPECT_EQ(box.min().x(), next);
      EXPECT_EQ(box.min().x() % 8, 0);
      EXPECT_EQ(box.min().y(), 0);
      EXPECT_EQ(box.max().z(), spec.dims.z - 1);
      next = box.max().x() + 1;
    }
    EXPECT_EQ(next, spec.dims.x) << tiles << " tiles";
  }
}

TEST(TileBake, MergedTilesEqualTheWholeBake) {
  const BakeOptions bake = bunnyBake(48);
  const Scene scene = loadScene(bake.scene);
  const BakeResult whole = rtsdf::bake(scene, bake);
  const GridSpec spec = tiledBakeGrid(scene, bake);
  ASSERT_EQ(spec.dims, whole.spec.dims);
  for (int tiles : {1, 3, 5, 9}) { // 9 slabs of a grid 7 leaves long: two are empty
    const auto grids = bakeTiles(scene, bake, tiles);
    const auto boxes = tileBoxes(spec, tiles);
    openvdb::Index64 active = 0;
    for (int t = 0; t < tiles; ++t) {
      active += grids[t]->activeVoxelCount();
      for (auto leaf = grids[t]->tree().cbeginLeaf(); leaf; ++leaf)
        EXPECT_TRUE(boxes[t].isInside(leaf->origin())) << "tile " << t << " holds a leaf outside its slab";
    }
    EXPECT_EQ(active, whole.grid->activeVoxelCount());
    const auto merged = mergeTiles(grids);
    EXPECT_EQ(countDifferentValues(*merged, *whole.grid), 0u) << tiles << " tiles";
    EXPECT_EQ(merged->tree().leafCount(), whole.grid->tree().leafCount());
    EXPECT_EQ(merged->transform(), whole.grid->transform());
  }
}

TEST(TileBake, TheComparisonSeesOneVoxelAndAMissingTile) {
  const BakeOptions bake = bunnyBake(32);
  const Scene scene = loadScene(bake.scene);
  const BakeResult whole = rtsdf::bake(scene, bake);
  auto grids = bakeTiles(scene, bake, 3);
  const auto merged = mergeTiles(grids);
  ASSERT_EQ(countDifferentValues(*merged, *whole.grid), 0u);
  const openvdb::Coord c = whole.grid->cbeginValueOn().getCoord();
  merged->tree().setValueOn(c, merged->tree().getValue(c) + 1e-3f);
  EXPECT_EQ(countDifferentValues(*merged, *whole.grid), 2u); // seen from either grid
  auto two = bakeTiles(scene, bake, 3);
  two.pop_back();
  EXPECT_GT(countDifferentValues(*mergeTiles(two), *whole.grid), 100u);
}

TEST(TileBake, BadTilingsAreRefusedNamingTheSetting) {
  const Scene scene = loadScene(std::string(RTSDF_DATA_DIR) + "/scenes/bunny.json");
  auto refused = [&](TileBakeOptions o) {
    try {
      bakeTile(scene, o);
    } catch (const SettingError& e) {
      return e.setting();
    }
    return std::string("accepted");
  };
  TileBakeOptions o;
  o.bake = bunnyBake(32);
  o.tiles = 3;
  o.tile = 3;
  EXPECT_EQ(refused(o), "tile");
  o.tile = 0;
  o.tiles = 0;
  EXPECT_EQ(refused(o), "tiles");
  o.tiles = 2;
  o.bake.method = BakeMethod::OpenVdb;
  EXPECT_EQ(refused(o), "bake method");
  o.bake.method = BakeMethod::Exact;
  o.bake.fullDomain = true;
  EXPECT_EQ(refused(o), "full domain");
  EXPECT_THROW(mergeTiles({}), Error);
}
