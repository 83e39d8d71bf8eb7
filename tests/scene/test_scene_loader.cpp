#include "TestUtil.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <gtest/gtest.h>

using namespace rtsdf;
using rtsdf::test::TempDir;
using rtsdf::test::writeText;

namespace {

/// The error message parseScene gives for @a json, or "" when it parses.
std::string sceneError(const std::string& json, const std::filesystem::path& origin = "bad.json") {
  try {
    parseScene(json, origin);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kBox = R"("meshes": {"b": {"box": [1, 1, 1]}})";

} // namespace

TEST(SceneLoader, DefaultSceneLoads) {
  const Scene s = loadScene(test::dataPath("scenes/default.json"));
  EXPECT_EQ(s.instances.size(), 20u);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, Light::Type::Directional);
  EXPECT_GT(s.lights[0].angularRadius, 0.0);
  EXPECT_TRUE(s.hasCamera);
  std::size_t open = 0;
  for (const auto& r : s.meshReports) open += r.watertight() ? 0 : 1;
  EXPECT_EQ(open, 1u); // the teapot

  // The scene is about 2 units across and the objects do not interpenetrate their supports.
  const SceneGeometry g = buildSceneGeometry(s, 0.0);
  EXPECT_NEAR(g.bounds.maxExtent(), 2.0, 0.05);
  EXPECT_EQ(g.triangleCount(), 4882u);
}

TEST(SceneLoader, TeapotOrbits) {
  const Scene s = loadScene(test::dataPath("scenes/default.json"));
  const Instance* teapot = nullptr;
  for (const auto& i : s.instances)
    if (i.name == "teapot") teapot = &i;
  ASSERT_NE(teapot, nullptr);
  ASSERT_EQ(teapot->animation.kind, Animation::Kind::Orbit);
  const glm::dvec3 c = teapot->animation.center;
  const glm::dvec3 p0(teapot->matrixAt(0.0)[3]);
  const glm::dvec3 p1(teapot->matrixAt(0.5 * teapot->animation.period)[3]);
  const glm::dvec3 p2(teapot->matrixAt(teapot->animation.period)[3]);
  EXPECT_NEAR(glm::length(p0 - c), glm::length(p1 - c), 1e-9);
  EXPECT_NEAR(glm::length(p0 - p1), 2.0 * glm::length(glm::dvec2(p0.x - c.x, p0.z - c.z)), 1e-9); // opposite side
  EXPECT_NEAR(glm::length(p0 - p2), 0.0, 1e-9);                                                   // full turn
}

TEST(SceneLoader, KeyframesInterpolateAndClamp) {
  const Scene s = parseScene(std::string("{") + kBox + R"(, "instances": [{"mesh": "b", "animation": {"keyframes": [
      {"time": 0, "translate": [0, 0, 0]}, {"time": 2, "translate": [2, 0, 0], "rotate": {"axis": [0, 1, 0], "degrees": 90}}]}}]})",
                             "k.json");
  const Instance& in = s.instances[0];
  EXPECT_NEAR(in.matrixAt(1.0)[3].x, 1.0, 1e-12);
  EXPECT_NEAR(in.matrixAt(-5.0)[3].x, 0.0, 1e-12);
  EXPECT_NEAR(in.matrixAt(9.0)[3].x, 2.0, 1e-12);
  // Halfway: 45 degrees about y maps +x to (cos 45, 0, -sin 45).
  const glm::dvec3 x = glm::dvec3(in.matrixAt(1.0) * glm::dvec4(1, 0, 0, 0));
  EXPECT_NEAR(x.x, std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(x.z, -std::sqrt(0.5), 1e-9);
}

TEST(SceneLoader, MirroringTransformKeepsOutsideOutside) {
  const Scene s =
      parseScene(std::string("{") + kBox + R"(, "instances": [{"mesh": "b", "scale": [-1, 1, 1]}]})", "m.json");
  const SceneGeometry g = buildSceneGeometry(s);
  EXPECT_NEAR(test::signedVolume(g.meshes[0].positions, g.meshes[0].triangles), 1.0, 1e-9);
}

TEST(SceneLoader, MeshFileAsScene) {
  const Scene s = loadScene(test::dataPath("meshes/bunny.obj"));
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.meshReports[0].triangles, 3674u);
}

TEST(SceneLoader, ErrorsNameFileAndKey) {
  struct Case { const char* json; const char* expect; };
  const std::string b = kBox;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ not json", "malformed JSON"},
      {"[]", "must be an object"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "colour": 1}]})", "unknown key 'colour'"},
      {"{" + b + R"(, "instances": [{"mesh": "nope"}]})", "instances[0].mesh: no mesh named 'nope'"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "scale": 0}]})", "instances[0].scale: scale factors must not be zero"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "translate": [0, 1]}]})", "instances[0].translate"},
      {"{" + b + R"(, "instances": []})", "non-empty 'instances'"},
      {R"({"meshes": {}, "instances": [{"mesh": "b"}]})", "non-empty 'meshes'"},
      {R"({"meshes": {"b": {"box": [1, 0, 1]}}, "instances": [{"mesh": "b"}]})", "must be positive"},
      {R"({"meshes": {"b": {"path": "missing.obj"}}, "instances": [{"mesh": "b"}]})", "missing.obj: mesh file not found"},
      {"{" + b + R"(, "instances": [{"mesh": "b"}], "lights": [{"type": "spot"}]})", "lights[0].type"},
      {"{" + b + R"(, "instances": [{"mesh": "b"}], "lights": [{"type": "directional", "direction": [0, 0, 0]}]})",
       "non-zero vector"},
      {"{" + b + R"(, "instances": [{"mesh": "b"}], "camera": {"position": [0, 0, 0], "look_at": [0, 0, 0]}})",
       "must differ"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "animation": {"keyframes": [{"time": 1}, {"time": 1}]}}]})",
       "must increase"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "animation": {"orbit": {"period": 0}}}]})", "period: must be positive"},
      {"{" + b + R"(, "instances": [{"mesh": "b", "name": "x"}, {"mesh": "b", "name": "x"}]})", "duplicate instance"},
      {R"({"rtsdf_scene": 7, )" + b + R"(, "instances": [{"mesh": "b"}]})", "unsupported scene format"},
  };
  for (const auto& [json, expect] : cases) {
    SCOPED_TRACE(json);
    const std::string msg = sceneError(json);
    EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(expect), std::string::npos) << msg;
  }
}

TEST(SceneLoader, MissingSceneFileAndUnknownFormat) {
  TempDir dir;
  try {
    loadScene(dir / "nothing.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.json: scene file not found"), std::string::npos);
  }
  writeText(dir / "notes.txt", "hello");
  EXPECT_THROW(loadScene(dir / "notes.txt"), Error);
}

TEST(SceneLoader, MeshPathsAreRelativeToTheSceneFile) {
  TempDir dir;
  std::filesystem::create_directories(dir / "sub");
  writeText(dir / "sub" / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  writeText(dir / "s.json", R"({"meshes": {"t": {"path": "sub/tet.obj"}}, "instances": [{"mesh": "t"}]})");
  const Scene s = loadScene(dir / "s.json");
  EXPECT_EQ(s.meshReports[0].triangles, 4u);
}

TEST(SceneGeometry, TransformsThatBreakTrianglesAreErrors) {
  const Scene tiny =
      parseScene(R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", "scale": 1e-30}]})", "tiny.json");
  try {
    buildSceneGeometry(tiny);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no triangle of non-zero area"), std::string::npos) << e.what();
  }
  const Scene huge =
      parseScene(R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b", "scale": 1e40}]})", "huge.json");
  EXPECT_THROW(buildSceneGeometry(huge), Error);
}

TEST(SphereMesh, IcosphereIsClosedOutwardAndOnTheSphere) {
  for (int n : {0, 1, 3}) {
    Mesh m = makeSphereMesh(0.5f, n, "ball");
    EXPECT_EQ(m.name, "ball");
    EXPECT_EQ(m.triangles.size(), 20u << (2 * n));
    EXPECT_EQ(m.positions.size(), (10u << (2 * n)) + 2u);
    for (const glm::vec3& p : m.positions) EXPECT_NEAR(glm::length(p), 0.5f, 1e-6f);
    // Outward: positive volume, below the sphere's and approaching it with subdivision.
    const double v = test::signedVolume(m.positions, m.triangles), ball = 4.0 / 3.0 * glm::pi<double>() * 0.125;
    EXPECT_GT(v, 0.0);
    EXPECT_LT(v, ball);
    if (n == 3) EXPECT_NEAR(v / ball, 1.0, 0.02);
    const MeshReport r = validateMesh(m);
    EXPECT_TRUE(r.watertight());
    EXPECT_EQ(r.degenerateDropped, 0u);
    EXPECT_EQ(r.weldedVertices, 0u);
  }
  EXPECT_THROW(makeSphereMesh(0.0f, 2), Error);
  EXPECT_THROW(makeSphereMesh(-1.0f, 2), Error);
  EXPECT_THROW(makeSphereMesh(INFINITY, 2), Error);
  EXPECT_THROW(makeSphereMesh(1.0f, -1), Error);
  EXPECT_THROW(makeSphereMesh(1.0f, 8), Error);
}

TEST(SceneLoader, SphereMeshes) {
  const Scene s = parseScene(R"({"meshes": {"ball": {"sphere": {"radius": 0.25, "subdivisions": 2}},
                                            "dflt": {"sphere": {"radius": 2}}},
                                 "instances": [{"mesh": "ball", "translate": [0, 0.5, 0]}, {"mesh": "dflt"}]})",
                             "s.json");
  ASSERT_EQ(s.meshes.size(), 2u);
  const std::size_t ball = s.meshes[0].name == "ball" ? 0 : 1, dflt = 1 - ball;
  EXPECT_EQ(s.meshes[ball].name, "ball");
  EXPECT_EQ(s.meshes[ball].source, "<sphere>");
  EXPECT_EQ(s.meshReports[ball].triangles, 320u);
  EXPECT_TRUE(s.meshReports[ball].watertight());
  EXPECT_EQ(s.meshReports[dflt].triangles, 5120u); // default: 4 subdivisions
  for (const glm::vec3& p : s.meshes[ball].positions) EXPECT_NEAR(glm::length(p), 0.25f, 1e-6f);

  const Scene a = loadScene(test::dataPath("scenes/analytic.json"));
  ASSERT_EQ(a.instances.size(), 2u);
  EXPECT_EQ(a.meshReports[a.instances[1].mesh].triangles, 81920u);
  const SceneGeometry g = buildSceneGeometry(a);
  double top = -1.0;
  for (const glm::vec3& p : g.meshes[0].positions) top = std::max(top, double(p.y));
  EXPECT_NEAR(top, 0.0, 1e-6); // the floor's top face
}

TEST(SceneLoader, BadSpheresNameFileAndKey) {
  const std::string inst = R"(, "instances": [{"mesh": "s"}]})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"meshes": {"s": {"sphere": {"radius": -1}}})", "meshes.s.sphere.radius: must be positive"},
      {R"({"meshes": {"s": {"sphere": {"radius": 0}}})", "meshes.s.sphere.radius: must be positive"},
      {R"({"meshes": {"s": {"sphere": {"radius": "big"}}})", "meshes.s.sphere.radius: must be a number"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1e300}}})", "meshes.s.sphere.radius: must be finite"},
      {R"({"meshes": {"s": {"sphere": {"subdivisions": 2}}})", "meshes.s.sphere: needs 'radius'"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1, "subdivisions": 8}}})",
       "meshes.s.sphere.subdivisions: must be an integer in [0, 7] (got 8)"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1, "subdivisions": -1}}})", "meshes.s.sphere.subdivisions"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1, "subdivisions": 2.5}}})", "meshes.s.sphere.subdivisions"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1, "subdivisions": 3.0}}})", "meshes.s.sphere.subdivisions"},
      {R"({"meshes": {"s": {"sphere": {"radius": 1, "segments": 3}}})", "meshes.s.sphere: unknown key 'segments'"},
      {R"({"meshes": {"s": {"sphere": [1, 2]}})", "meshes.s.sphere: must be an object"},
      {R"({"meshes": {"s": {"box": [1, 1, 1], "sphere": {"radius": 1}}})",
       "meshes.s: needs exactly one of 'path', 'box' or 'sphere'"},
      {R"({"meshes": {"s": {"path": "x.obj", "sphere": {"radius": 1}}})", "needs exactly one of"},
      {R"({"meshes": {"s": {}})", "needs exactly one of"},
  };
  for (const auto& [meshes, expect] : cases) {
    const std::string json = meshes + inst;
    SCOPED_TRACE(json);
    const std::string msg = sceneError(json);
    EXPECT_NE(msg.find("bad.json: "), std::string::npos) << msg;
    EXPECT_NE(msg.find(expect), std::string::npos) << msg;
  }
}
