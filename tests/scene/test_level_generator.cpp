// scripts/make_level.py: the town level the cascades are measured on. Deterministic from its seed, and rtsdf loads
// what it writes.
#include "TestUtil.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace rtsdf;
namespace fs = std::filesystem;

namespace {

/// Run the generator into @a out; its exit status.
int makeLevel(const fs::path& out, double size, int seed) {
  int status = 0;
  const std::string cmd = "/usr/bin/python3 " + test::dataPath("../scripts/make_level.py") + " --out '" +
                          out.string() + "' --size " + std::to_string(size) + " --seed " + std::to_string(seed) +
                          " 2>&1";
  const std::string log = test::runCommand(cmd, status);
  EXPECT_EQ(status, 0) << log;
  return status;
}

/// Every file under @a dir by its path relative to it, with its bytes.
std::map<std::string, std::string> folderBytes(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) {
      std::ifstream in(e.path(), std::ios::binary);
      std::ostringstream s;
      s << in.rdbuf();
      files[fs::relative(e.path(), dir).string()] = s.str();
    }
  return files;
}

} // namespace

TEST(LevelGenerator, TheSameSeedWritesTheSameBytesAndAnotherSeedAnotherLevel) {
  test::TempDir dir;
  ASSERT_EQ(makeLevel(dir / "a", 50, 3), 0);
  ASSERT_EQ(makeLevel(dir / "b", 50, 3), 0);
  ASSERT_EQ(makeLevel(dir / "c", 50, 4), 0);
  const auto a = folderBytes(dir / "a"), b = folderBytes(dir / "b"), c = folderBytes(dir / "c");
  ASSERT_GE(a.size(), 11u); // level.json, 6 buildings, car, bench, bunny, teapot
  EXPECT_EQ(a, b);
  EXPECT_NE(a.at("level.json"), c.at("level.json"));
}

TEST(LevelGenerator, RtsdfLoadsEachSizeWithItsCameraPathAndMovingVehicles) {
  test::TempDir dir;
  for (const double size : {50.0, 200.0}) {
    const fs::path out = dir / ("level" + std::to_string(int(size)));
    ASSERT_EQ(makeLevel(out, size, 1), 0);
    const Scene scene = loadScene(out / "level.json");
    ASSERT_TRUE(scene.hasCamera);
    ASSERT_GE(scene.cameraPath.size(), 4u);
    ASSERT_FALSE(scene.lights.empty());
    // Walking at 1.4 m/s over the first keyframes, driving at 12 m/s at the end.
    const auto speed = [&](std::size_t k) {
      const CameraKeyframe &a = scene.cameraPath[k], &b = scene.cameraPath[k + 1];
      return glm::length(b.position - a.position) / (b.time - a.time);
    };
    EXPECT_NEAR(speed(0), 1.4, 1e-3);
    EXPECT_NEAR(speed(scene.cameraPath.size() - 2), 12.0, 1e-2);
    // The world spans the level; the camera stays inside it at every moment.
    const SceneGeometry g = buildSceneGeometry(scene, 0.0);
    EXPECT_GE(g.bounds.max.x - g.bounds.min.x, size);
    for (double t = 0.0; t < scene.cameraPath.back().time; t += 0.5) {
      const glm::dvec3 p = scene.cameraAt(t).position;
      EXPECT_LT(std::max(std::abs(p.x), std::abs(p.z)), size / 2) << "t = " << t;
    }
    // Cars move: some instance is somewhere else a second later, walls are thin.
    std::size_t moving = 0;
    for (const Instance& in : scene.instances)
      if (in.animation.kind == Animation::Kind::Keyframes &&
          glm::length(glm::dvec3(in.matrixAt(1.0)[3] - in.matrixAt(0.0)[3])) > 5.0)
        ++moving;
    EXPECT_GE(moving, 2u);
    EXPECT_GE(scene.meshes.size(), 11u);
  }
}
