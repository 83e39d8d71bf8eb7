// Cascade levels without a GPU: where the levels lie for a camera (snapped, nested, no swimming), what each level
// sees of the scene, the memory they need over worlds of 50, 200 and 1000 m, and the warning that one box is too
// coarse for its scene.
#include "TestUtil.h"
#include "TownOfRooms.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/cascade/CascadeLayout.h"
#include "sdf/cascade/CascadeMemory.h"
#include "sdf/cascade/CascadeSamplerCpu.h"
#include "sdf/cascade/CascadeScene.h"
#include "sdf/cascade/SingleBoxCheck.h"
#include "sdf/cascade/ToroidalLevelCpu.h"
#include "sdf/pipeline/GridShift.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace rtsdf;

namespace {

CascadeShape shape4() {
  CascadeShape s;
  s.levels = 4;
  s.coarseRes = 64;
  s.fineRes = 256;
  s.levelZeroExtent = 6.25;
  s.moveCells = levelMoveCells(s.coarseRes, s.fineRes); // 2: a brick of 8 fine voxels is 2 coarse ones
  return s;
}

/// Whether @a x is a whole multiple of @a step, exactly.
bool wholeMultiple(double x, double step) { return std::floor(x / step) == x / step; }

bool inside(const Bounds& inner, const Bounds& outer) {
  return glm::all(glm::greaterThanEqual(inner.min, outer.min)) && glm::all(glm::lessThanEqual(inner.max, outer.max));
}
bool holds(const Bounds& b, const glm::dvec3& p) {
  return glm::all(glm::greaterThanEqual(p, b.min)) && glm::all(glm::lessThanEqual(p, b.max));
}

} // namespace

TEST(CascadeLayout, LevelsDoubleTheirVoxelsAndSnapToTheirCoarseVoxel) {
  const CascadeShape shape = shape4();
  const glm::dvec3 camera(12.3456, 1.7, -98.765);
  const CascadeLayout layout = CascadeLayout::around(camera, shape);
  ASSERT_EQ(layout.levels.size(), 4u);
  for (const CascadeLevel& l : layout.levels) {
    const double c = shape.levelZeroExtent / shape.coarseRes * std::ldexp(1.0, l.index);
    EXPECT_EQ(l.coarse.voxelSize, c);
    EXPECT_EQ(l.fine.voxelSize, shape.levelZeroExtent / shape.fineRes * std::ldexp(1.0, l.index));
    EXPECT_EQ(l.coarse.dims, glm::ivec3(64));
    EXPECT_EQ(l.fine.dims, glm::ivec3(256));
    EXPECT_EQ(l.coarse.origin, l.fine.origin) << "the coarse grid shares the fine one's corner";
    for (int a = 0; a < 3; ++a) {
      EXPECT_TRUE(wholeMultiple(l.coarse.origin[a], c * shape.moveCells)) << "level " << l.index << " axis " << a;
      // Centred on the camera to within half a move.
      EXPECT_LE(std::abs(l.box().center()[a] - camera[a]), 0.5 * c * shape.moveCells + 1e-12) << l.index;
    }
    if (l.index > 0) EXPECT_TRUE(inside(layout.levels[std::size_t(l.index) - 1].box(), l.box())) << l.index;
  }
  EXPECT_EQ(layout.finestHolding(camera), 0);
  EXPECT_EQ(layout.finestHolding(camera + glm::dvec3(10, 0, 0)), 2); // level 0 spans ±3.1, level 1 ±6.25
  EXPECT_EQ(layout.finestHolding(camera + glm::dvec3(1000, 0, 0)), -1);
}

// Levels centred ahead of the camera (lookAhead: 0.4 of level 0's side along a diagonal view, as the renderer places
// them) reach far further into the view than behind it, still nest, and each still holds the camera; the outermost
// stays centred on the camera.
TEST(CascadeLayout, LevelsAheadOfTheCameraStillNestAndHoldTheCamera) {
  const CascadeShape shape = shape4();
  const glm::dvec3 camera(12.3456, 1.7, -98.765), forward = glm::normalize(glm::dvec3(-1.0, -0.6, -1.1));
  const glm::dvec3 ahead = forward * (0.4 * shape.levelZeroExtent);
  const CascadeLayout layout = CascadeLayout::around(camera, shape, ahead);
  for (const CascadeLevel& l : layout.levels) {
    const double side = shape.levelZeroExtent * std::ldexp(1.0, l.index), c = shape.coarseVoxel(l.index);
    const bool outermost = l.index + 1 == shape.levels;
    for (int a = 0; a < 3; ++a) {
      EXPECT_TRUE(wholeMultiple(l.coarse.origin[a], c * shape.moveCells)) << "level " << l.index << " axis " << a;
      const double centre = outermost ? camera[a] : camera[a] + std::ldexp(ahead[a], l.index);
      EXPECT_LE(std::abs(l.box().center()[a] - centre), 0.5 * c * shape.moveCells + 1e-12);
    }
    EXPECT_TRUE(holds(l.box(), camera)) << l.index;
    if (l.index > 0) EXPECT_TRUE(inside(layout.levels[std::size_t(l.index) - 1].box(), l.box())) << l.index;
    if (outermost) continue;
    // Along the view the level reaches 0.9 of its side ahead and 0.1 behind (to the snapping).
    const glm::dvec3 far = camera + forward * (0.8 * side), near = camera - forward * (0.05 * side);
    EXPECT_TRUE(holds(l.box(), far) && holds(l.box(), near)) << l.index;
    EXPECT_FALSE(holds(l.box(), camera - forward * (0.5 * side))) << l.index;
  }
  EXPECT_EQ(layout.lookAhead, ahead);
}

// Any look-ahead is clamped to CascadeShape::maxLookAhead(), and up to it the levels nest with a fine voxel of the
// coarser level to spare (where the march blends into it) for every camera, however the levels snap, and each level
// holds the camera: random cameras and look-aheads over shapes with even, odd and mixed voxel counts. The levels lie on
// lattices of whole moves, so the spare room comes in steps of a move: some cameras leave less than one move (the bound
// is not loose); without the snapping in it, the nesting fails for some.
TEST(CascadeLayout, AnyLookAheadIsClampedSoThatTheLevelsNestWithAFineVoxelToSpare) {
  struct Counts {
    int coarse, fine;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Counts counts : {Counts{64, 256}, Counts{64, 128}, Counts{32, 64}, Counts{63, 126}, Counts{48, 80}}) {
    CascadeShape shape = shape4();
    shape.coarseRes = counts.coarse;
    shape.fineRes = counts.fine;
    shape.moveCells = levelMoveCells(shape.coarseRes, shape.fineRes);
    const double reach = shape.maxLookAhead();
    EXPECT_GT(reach, 0.25 * shape.levelZeroExtent) << counts.coarse << "/" << counts.fine;
    int tight = 0;
    for (int k = 0; k < 3000; ++k) {
      const glm::dvec3 camera(100.0 * u(rng), 10.0 * u(rng), 100.0 * u(rng));
      // Half the look-aheads asked for twice level 0's side along a random view (clamped), half along an axis,
      // within two moves of the reach (where the snapping decides the gap).
      glm::dvec3 ahead = glm::dvec3(u(rng), u(rng), u(rng)) * (2.0 * shape.levelZeroExtent);
      if (k % 2 == 0) {
        ahead = glm::dvec3(0.0);
        ahead[k / 2 % 3] = (u(rng) < 0.0 ? -1.0 : 1.0) * (reach - 2.0 * std::fabs(u(rng)) * shape.moveCells *
                                                                     shape.coarseVoxel(0));
      }
      const CascadeLayout layout = CascadeLayout::around(camera, shape, ahead);
      ASSERT_TRUE(glm::all(glm::lessThanEqual(glm::abs(layout.lookAhead), glm::dvec3(reach))));
      for (const CascadeLevel& l : layout.levels) {
        ASSERT_TRUE(holds(l.box(), camera)) << "level " << l.index;
        if (l.index == 0) continue;
        const Bounds inner = layout.levels[std::size_t(l.index) - 1].box(), outer = l.box();
        const Bounds spare{outer.min + l.fine.voxelSize, outer.max - l.fine.voxelSize};
        ASSERT_TRUE(inside(inner, spare)) << counts.coarse << "/" << counts.fine << " level " << l.index << " camera "
                                          << camera.x << " " << camera.y << " " << camera.z;
        const glm::dvec3 gap = glm::min(inner.min - spare.min, spare.max - inner.max);
        tight += std::min({gap.x, gap.y, gap.z}) < shape.coarseVoxel(l.index - 1) * shape.moveCells;
      }
    }
    EXPECT_GT(tight, 0) << "some cameras come within a move of the bound: it is not loose";
  }
}

TEST(CascadeLayout, ACameraPathMovesLevelsByWholeMovesOnly) {
  const CascadeShape shape = shape4();
  CascadeLayout before = CascadeLayout::around({0.01, 1.7, 0.02}, shape);
  std::vector<std::int64_t> moves(4, 0);
  for (int step = 1; step <= 400; ++step) {
    // Walking then driving: 1.4 m/s at 30 frames per second, then 12 m/s, along a diagonal.
    const double s = step <= 200 ? step * 1.4 / 30 : 200 * 1.4 / 30 + (step - 200) * 12.0 / 30;
    const CascadeLayout now = CascadeLayout::around({0.01 + s, 1.7, 0.02 + 0.5 * s}, shape);
    const auto shift = now.shiftSince(before);
    for (std::size_t i = 0; i < 4; ++i) {
      const double c = shape.coarseVoxel(int(i));
      // The same lattice before and after: the old voxel centres are new voxel centres (no swimming).
      const glm::dvec3 moved =
          (now.levels[i].fine.origin - before.levels[i].fine.origin) / now.levels[i].fine.voxelSize;
      EXPECT_EQ(moved, glm::floor(moved)) << "level " << i << " step " << step;
      EXPECT_EQ(now.levels[i].coarse.origin - before.levels[i].coarse.origin, glm::dvec3(shift[i]) * c);
      // By whole moves (whole bricks of the fine grid: what a level scrolls by).
      EXPECT_EQ(shift[i] % std::int64_t(shape.moveCells), glm::i64vec3(0)) << "level " << i << " step " << step;
      EXPECT_TRUE(scrollShift(before.levels[i].grids(), now.levels[i].grids()).has_value() ||
                  glm::any(glm::greaterThanEqual(glm::abs(shift[i]), glm::i64vec3(shape.coarseRes))));
      moves[i] += std::abs(shift[i].x) + std::abs(shift[i].y) + std::abs(shift[i].z);
    }
    before = now;
  }
  // Coarser levels move less often: the slabs that enter a level shrink by half per level.
  for (std::size_t i = 1; i < 4; ++i) EXPECT_LT(moves[i], moves[i - 1]) << i;
  EXPECT_GT(moves[3], 0);
}

// A level moves by the fewest coarse voxels that are whole bricks, and the grids' scroll is recognised only then.
TEST(CascadeLayout, LevelsMoveByWholeBricksAndScrollOnlyByThem) {
  EXPECT_EQ(levelMoveCells(64, 128), 4);
  EXPECT_EQ(levelMoveCells(64, 256), 2);
  EXPECT_EQ(levelMoveCells(64, 512), 1);
  EXPECT_EQ(levelMoveCells(32, 32), 8);
  EXPECT_EQ(levelMoveCells(64, 96), 1) << "fine voxels straddling coarse ones: no scroll";
  CascadeShape shape = shape4();
  const CascadeLevel a = CascadeLayout::around({0, 0, 0}, shape).levels[1];
  CascadeLevel b = a;
  const double c = a.coarse.voxelSize;
  b.coarse.origin = b.fine.origin = a.coarse.origin + glm::dvec3(2 * c, -4 * c, 0);
  EXPECT_EQ(scrollShift(a.grids(), b.grids()), std::optional<glm::ivec3>(glm::ivec3(2, -4, 0)));
  b.coarse.origin = b.fine.origin = a.coarse.origin + glm::dvec3(c, 0, 0);
  EXPECT_FALSE(scrollShift(a.grids(), b.grids())) << "half a brick";
  b.coarse.origin = b.fine.origin = a.coarse.origin + glm::dvec3(64 * c, 0, 0);
  EXPECT_FALSE(scrollShift(a.grids(), b.grids())) << "nothing kept";
  b = a;
  b.fine.voxelSize *= 2;
  EXPECT_FALSE(scrollShift(a.grids(), b.grids())) << "another grid";
}

// The transfers of a shift leave every cell what a shift cell by cell gives, entered cells filled.
TEST(GridShift, ThePlanEqualsAShiftCellByCell) {
  for (const glm::ivec3 dims : {glm::ivec3(5, 4, 3), glm::ivec3(8, 1, 6)})
    for (const std::uint32_t elementWords : {1u, 2u})
      for (const glm::ivec3 shift : {glm::ivec3(0), glm::ivec3(2, 0, 0), glm::ivec3(-1, 3, 0), glm::ivec3(0, 0, -2),
                                     glm::ivec3(1, -1, 1), glm::ivec3(7, 0, 0), glm::ivec3(0, 0, 3)}) {
        SCOPED_TRACE(testing::Message() << dims.x << "x" << dims.y << "x" << dims.z << " shift " << shift.x << ","
                                        << shift.y << "," << shift.z << " words " << elementWords);
        const std::size_t cells = std::size_t(dims.x) * dims.y * dims.z;
        std::vector<std::uint32_t> words(cells * elementWords);
        for (std::size_t i = 0; i < words.size(); ++i) words[i] = std::uint32_t(i) + 1;
        std::vector<std::uint32_t> expected(words.size());
        for (int z = 0; z < dims.z; ++z)
          for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
              const glm::ivec3 from = glm::ivec3(x, y, z) + shift;
              const bool kept = glm::all(glm::greaterThanEqual(from, glm::ivec3(0))) && glm::all(glm::lessThan(from, dims));
              const std::size_t to = std::size_t((z * dims.y + y) * dims.x + x);
              const std::size_t src = kept ? std::size_t((from.z * dims.y + from.y) * dims.x + from.x) : 0;
              for (std::uint32_t w = 0; w < elementWords; ++w)
                expected[to * elementWords + w] = kept ? words[src * elementWords + w] : 0xABCDu;
            }
        // Loose: one copy at most, every kept cell right (the entered ones hold anything).
        std::vector<std::uint32_t> loose = words;
        const GridShiftPlan loosePlan = gridShiftPlanLoose(dims, 4 * elementWords, shift);
        EXPECT_LE(loosePlan.copies.size(), 1u);
        EXPECT_TRUE(loosePlan.fills.empty());
        applyGridShift(loosePlan, loose, 0xABCDu);
        for (std::size_t k = 0; k < loose.size(); ++k)
          if (expected[k] != 0xABCDu) EXPECT_EQ(loose[k], expected[k]) << "word " << k;
        const GridShiftPlan plan = gridShiftPlan(dims, 4 * elementWords, shift);
        applyGridShift(plan, words, 0xABCDu);
        EXPECT_EQ(words, expected);
        if (shift == glm::ivec3(0)) EXPECT_TRUE(plan.fills.empty() && plan.copies.size() == 1u) << "one copy";
      }
  EXPECT_EQ(gridShiftPlan({4, 4, 4}, 4, {0, 0, 1}).copies.size(), 1u) << "a shift along z is one copy";
  EXPECT_THROW(gridShiftPlan({4, 4, 4}, 6, {0, 0, 0}), Error);
}

TEST(CascadeLayout, TheDefaultExtentMakesTheOutermostLevelSpanTheScene) {
  PipelineSettings s;
  s.cascades = 3;
  Bounds b{{-10, 0, -40}, {10, 5, 40}};
  const CascadeShape shape = cascadeShapeFor(b, s);
  EXPECT_EQ(shape.levelZeroExtent, 20.0);
  EXPECT_EQ(CascadeLayout::around({0, 0, 0}, shape).levels.back().box().extent().z, 80.0);
  s.cascadeExtent = 4.0;
  EXPECT_EQ(cascadeShapeFor(b, s).levelZeroExtent, 4.0);
  s.cascades = 11;
  try {
    cascadeShapeFor(b, s);
    FAIL() << "11 levels are refused";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.setting(), "cascades");
    EXPECT_NE(std::string(e.what()).find("[1, 10]"), std::string::npos) << e.what();
  }
  s.cascades = 2;
  s.cascadeExtent = 0.0;
  EXPECT_THROW(cascadeShapeFor(b, s), SettingError) << "a level of no size";
}

TEST(CascadeScene, ALevelKeepsTheInstancesNearItsBoxAndEveryMovingOne) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  // A box around the table top only: the bunny on it, the table, and the orbiting teapot (it moves).
  const Bounds box{{-0.4, 0.34, -0.05}, {-0.3, 0.4, 0.05}};
  const Scene all = levelScene(scene, {{-10, -10, -10}, {10, 10, 10}}, 0.0);
  EXPECT_EQ(all.instances.size(), scene.instances.size());
  EXPECT_EQ(instanceTriangles(all), instanceTriangles(scene));
  const Scene near = levelScene(scene, box, 0.05);
  EXPECT_LT(near.instances.size(), scene.instances.size());
  EXPECT_LT(near.meshes.size(), scene.meshes.size()) << "only the meshes the kept instances use";
  std::map<std::string, std::size_t> trianglesByInstance;
  for (const Instance& inst : scene.instances)
    trianglesByInstance[inst.name] = scene.meshes[inst.mesh].triangles.size();
  bool teapot = false, bunny = false, backWall = false;
  for (const Instance& inst : near.instances) {
    teapot = teapot || inst.name == "teapot";
    bunny = bunny || inst.name == "bunny";
    backWall = backWall || inst.name == "back_wall";
    ASSERT_LT(inst.mesh, near.meshes.size());
    EXPECT_EQ(near.meshes[inst.mesh].triangles.size(), trianglesByInstance.at(inst.name)) << "mesh renumbered";
  }
  EXPECT_TRUE(teapot) << "moving instances are kept";
  EXPECT_TRUE(bunny) << "the bunny sits on the table";
  EXPECT_FALSE(backWall) << "the back wall is far from the table";
}

TEST(CascadeMemory, DeviceMemoryStaysNearlyConstantFrom50To1000Metres) {
  test::TempDir dir;
  PipelineSettings s;
  s.coarseRes = 64;
  s.fineRes = 256;
  s.band = 0.1;
  s.cascades = 4;
  s.cascadeExtent = 6.25; // level 0: 2.4 cm fine voxels; level 3: 50 m
  std::vector<std::uint64_t> device;
  std::vector<double> singleBoxVoxel;
  for (const int size : {50, 200, 1000}) {
    std::string log;
    const std::string level = test::makeLevel((dir / std::to_string(size)).string(), size, log);
    ASSERT_FALSE(level.empty()) << log;
    const Scene town = loadScene(level);
    const Bounds bounds = buildSceneGeometry(town, 0.0).bounds;
    const CascadeLayout layout = CascadeLayout::around({0.3, 1.7, 0.4}, cascadeShapeFor(bounds, s));
    const CascadeMemory m = estimateCascadeMemory(town, layout, s);
    device.push_back(m.deviceBytes);
    std::printf("%d m: %s\n", size, m.describe().c_str());
    // One box fitted to the town at the same counts: the same grid memory, but its voxel grows with the town.
    PipelineSettings one = s;
    one.cascades = 1;
    const PipelineMemory single = estimatePipelineMemory(bounds, one, sceneGpuSize(town));
    singleBoxVoxel.push_back(single.fine.voxelSize);
    std::printf("%d m: one box %s, %llu triangles\n", size, single.describe().c_str(),
                (unsigned long long)instanceTriangles(town));
    EXPECT_EQ(layout.levels[0].fine.voxelSize, 6.25 / 256) << "level 0 keeps its voxel in every world";
  }
  for (std::size_t i = 1; i < device.size(); ++i)
    EXPECT_LT(std::abs(double(device[i]) - double(device[0])), 0.05 * double(device[0])) << i;
  EXPECT_GT(singleBoxVoxel[2], 15.0 * singleBoxVoxel[0]);
}

namespace {


std::string adviceAtRenderDefaults(const Scene& scene) {
  PipelineSettings s;
  s.coarseRes = 64;
  s.fineRes = 256;
  const auto [coarse, fine] = pipelineGrids(buildSceneGeometry(scene, 0.0).bounds, s);
  return singleBoxAdvice(scene, coarse, fine);
}

} // namespace

TEST(SingleBoxCheck, TheEightByEightTownOfRoomsWarnsAndNamesTheCascades) {
  EXPECT_EQ(adviceAtRenderDefaults(test::tiledRooms(1)), "") << "the room alone suits one box";
  const std::string eight = adviceAtRenderDefaults(test::tiledRooms(8));
  EXPECT_NE(eight.find("--cascades"), std::string::npos) << eight;
  EXPECT_NE(eight.find("coarse voxels on the shortest axis"), std::string::npos) << eight;
  EXPECT_NE(eight.find("of a typical feature"), std::string::npos) << eight;
  EXPECT_LT(eight.size(), 240u) << "one short line";
  EXPECT_NE(adviceAtRenderDefaults(test::tiledRooms(4)), "");
}

TEST(ToroidalLevelCpu, SlabUpdatesAlongACameraPathEqualAFullRebuildVoxelForVoxel) {
  const Scene scene = loadScene(test::dataPath("scenes/default.json"));
  const SceneGeometry geo = buildSceneGeometry(scene, 0.0);
  std::vector<glm::dvec3> corners;
  for (const WorldMesh& m : geo.meshes)
    for (const glm::uvec3& t : m.triangles)
      for (int k = 0; k < 3; ++k) corners.push_back(glm::dvec3(m.positions[t[k]]));
  CascadeShape shape;
  shape.levels = 2;
  shape.coarseRes = 40;
  shape.fineRes = 80;
  shape.levelZeroExtent = 1.0;
  for (int level = 0; level < 2; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    ToroidalLevelCpu moving(corners, 3);
    glm::dvec3 camera(-0.8, 0.4, -0.7);
    moving.rebuild(CascadeLayout::around(camera, shape).levels[std::size_t(level)]);
    const std::uint64_t full = moving.transformedLast();
    std::uint64_t moves = 0, transformed = 0, voxelized = 0;
    for (int step = 0; step < 40; ++step) {
      // Walking, then faster, on a diagonal that also climbs: slabs enter along every axis, in both directions.
      const double speed = step < 20 ? 0.02 : 0.09;
      camera += speed * glm::dvec3(1.0, step % 7 == 0 ? -0.5 : 0.2, step < 30 ? 0.8 : -0.9);
      const CascadeLevel where = CascadeLayout::around(camera, shape).levels[std::size_t(level)];
      moving.moveTo(where);
      ToroidalLevelCpu fresh(corners, 3);
      fresh.rebuild(where);
      ASSERT_EQ(moving.seeds(), fresh.seeds()) << "step " << step;
      ASSERT_EQ(moving.distances(), fresh.distances()) << "step " << step;
      if (moving.transformedLast() > 0) {
        ++moves;
        transformed += moving.transformedLast();
        voxelized += moving.voxelizedLast();
      }
    }
    EXPECT_GT(moves, 5u);
    // A move touches slabs, not the level: per moved axis the entered slab (m voxels) and the clamp's margins (3 + 3
    // voxels) of 40, under half of a full rebuild on average along this diagonal path.
    EXPECT_LT(double(transformed) / double(moves), 0.5 * double(full));
    EXPECT_LT(double(voxelized) / double(moves), 0.15 * double(full));
    std::printf("level %d: %llu moves, per move %.1f%% voxelized, %.1f%% transformed of a full rebuild\n", level,
                (unsigned long long)moves, 100.0 * double(voxelized) / double(moves) / double(full),
                100.0 * double(transformed) / double(moves) / double(full));
  }
}

TEST(ToroidalLevelCpu, AMoveChangesVoxelsItKeepsAndTheUpdateFollows) {
  // A wall just outside the level: once the level moves over it, voxels the level kept (they were inside before)
  // get nearer seeds, so an update that rewrote only the entered slab would leave them stale.
  const std::vector<glm::dvec3> wall = {{0.85, -1, -1}, {0.85, 1, -1}, {0.85, -1, 1}};
  CascadeShape shape;
  shape.levels = 1;
  shape.coarseRes = 16;
  shape.fineRes = 16;
  shape.levelZeroExtent = 1.6; // coarse voxel 0.1: the level spans [-0.8, 0.8], the wall is in cell 8
  ToroidalLevelCpu a(wall, 3), b(wall, 3);
  a.rebuild(CascadeLayout::around({0, 0, 0}, shape).levels[0]);
  const std::vector<float> before = a.distances();
  // World cell (7, 0, 0): level index (15, 8, 8) before.
  EXPECT_EQ(before[std::size_t((8 * 16 + 8) * 16 + 15)], 3.0f) << "no seed within the clamp yet";
  const CascadeLevel moved = CascadeLayout::around({0.38, 0, 0}, shape).levels[0];
  ASSERT_EQ(moved.centreCell.x, 4);
  a.moveTo(moved);
  b.rebuild(moved);
  EXPECT_EQ(a.seeds(), b.seeds());
  EXPECT_EQ(a.distances(), b.distances());
  // The same world cell is level index (11, 8, 8) now, one cell from the wall.
  EXPECT_EQ(a.distances()[std::size_t((8 * 16 + 8) * 16 + 11)], 1.0f);
  EXPECT_LT(a.transformedLast(), 16u * 16u * 16u);
}

namespace {

/// Level @a level's fine voxels filled with the distance to a sphere (centre @a c, radius @a r): each level holds
/// the closed form at its own voxel centres.
std::vector<float> sphereOnLevel(const CascadeLevel& level, const glm::dvec3& c, double r) {
  return test::sphereField(level.fine, c, r);
}

/// The largest change of @a sampler between samples @a step apart along the segment from @a a to @a b.
double largestStep(const CascadeSamplerCpu& sampler, const glm::dvec3& a, const glm::dvec3& b, double step) {
  const glm::dvec3 dir = glm::normalize(b - a);
  const int n = int(glm::length(b - a) / step);
  double worst = 0.0;
  float previous = sampler.sample(a);
  for (int k = 1; k <= n; ++k) {
    const float v = sampler.sample(a + double(k) * step * dir);
    worst = std::max(worst, double(std::fabs(v - previous)));
    previous = v;
  }
  return worst;
}

} // namespace

TEST(CascadeSamplerCpu, LevelBordersBlendWithoutASeamOnAClosedFormSphere) {
  CascadeShape shape;
  shape.levels = 3;
  shape.coarseRes = 16;
  shape.fineRes = 32;
  shape.levelZeroExtent = 1.0;
  const glm::dvec3 camera(0.013, 0.021, 0.007);
  const CascadeLayout layout = CascadeLayout::around(camera, shape);
  const double h0 = layout.levels[0].fine.voxelSize, h1 = layout.levels[1].fine.voxelSize;
  // A small sphere (radius 4 level-1 voxels) straddling level 0's border on the +x side, off the sampled line: the
  // levels' trilinear values differ most there (curvature), which a hard switch shows as a step.
  const double border = layout.levels[0].box().max.x - h0;
  const double radius = 4.0 * h1;
  const glm::dvec3 centre(border + 0.3 * radius, camera.y + 0.3 * radius, camera.z + 0.2 * radius);
  std::vector<std::vector<float>> fields;
  for (const CascadeLevel& l : layout.levels) fields.push_back(sphereOnLevel(l, centre, radius));
  const CascadeSamplerCpu blended(layout, fields, 4.0), hard(layout, fields, 0.0);
  const glm::dvec3 from = camera, to = camera + glm::dvec3(1.5, 0.0, 0.0); // out past level 1's border
  const double step = 1e-4;
  const double smooth = largestStep(blended, from, to, step), seam = largestStep(hard, from, to, step);
  std::printf("largest change per %g step: blended %.3g, hard switch %.3g\n", step, smooth, seam);
  // Each level's trilinear field changes by at most the step (a distance field is 1-Lipschitz); the blend adds the
  // levels' difference over the band, small. A hard switch jumps by that difference at once.
  EXPECT_LT(smooth, 1.1 * step);
  EXPECT_GT(seam, 5.0 * step);
  // Deep inside level 0 the sample is level 0's; on the margin itself it is level 1's.
  const glm::dvec3 deep = camera + glm::dvec3(0.1, 0.05, 0.0);
  EXPECT_EQ(blended.sample(deep), blended.sampleLevel(0, deep));
  const glm::dvec3 onMargin(border, camera.y + 0.3 * radius, camera.z + 0.2 * radius);
  EXPECT_NEAR(blended.sample(onMargin), blended.sampleLevel(1, onMargin), 1e-6);
  EXPECT_THROW(CascadeSamplerCpu(layout, {fields[0]}, 1.0), Error) << "a field per level";
}
